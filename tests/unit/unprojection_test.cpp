#include "devices/synthetic/synthetic_device.h"
#include "processing/point_cloud.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

namespace dc::processing {
namespace {

// Double-precision reference of the pinhole unprojection.
std::array<double, 3> reference(double u, double v, double z, double fx, double fy, double cx, double cy) {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
}

void expectRelativelyNear(float actual, double expected, double scale) {
    EXPECT_LE(std::abs(actual - expected), 1e-6 * scale) << actual << " vs " << expected;
}

TEST(Unprojection, MatchesDoubleReferenceAcrossTheImageAndDepthRange) {
    const frame::Intrinsics k{211.5, 210.25, 127.3, 95.8, 256, 192};
    for (int v = 0; v < 192; v += 7) {
        for (int u = 0; u < 256; u += 5) {
            for (float z : {0.1f, 0.75f, 2.5f, 4.99f}) {
                const auto p = unproject(u, v, z, k);
                const auto r = reference(u, v, z, k.fx, k.fy, k.cx, k.cy);
                // Relative to the point's distance: float carries ~7 significant digits.
                const double scale = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
                expectRelativelyNear(p[0], r[0], scale);
                expectRelativelyNear(p[1], r[1], scale);
                expectRelativelyNear(p[2], r[2], scale);
            }
        }
    }
}

TEST(Unprojection, CloudUsesIntrinsicsScaledToTheDepthResolution) {
    devices::SyntheticConfig config;
    config.depthWidth = 64;
    config.depthHeight = 48;
    config.cameraWidth = 320;
    config.cameraHeight = 240;
    config.noise = false;
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    ASSERT_TRUE(device.start());
    const auto result = device.capture(std::chrono::seconds(5));
    ASSERT_EQ(result.kind, devices::CaptureResult::Kind::Frame);
    const frame::Frame& frame = *result.frame;

    // The camera intrinsics are for 320x240; the cloud must use them scaled by 64/320 per axis.
    const frame::Intrinsics& cam = frame.cameraIntrinsics;
    const double sx = 64.0 / 320.0, sy = 48.0 / 240.0;
    const auto cloud = buildPointCloud(frame, frame::Confidence::Low, 0.0f);
    ASSERT_GT(cloud.size(), 1000u);
    std::size_t checked = 0;
    for (int v = 0; v < 48; ++v) {
        for (int u = 0; u < 64; ++u) {
            const float z = frame.sceneDepth->depthMeters.at(u, v);
            if (z <= 0.0f)
                continue;
            const auto r = reference(u, v, z, cam.fx * sx, cam.fy * sy, cam.cx * sx, cam.cy * sy);
            const CloudPoint& p = cloud[checked++];
            const double scale = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            expectRelativelyNear(p.x, r[0], scale);
            expectRelativelyNear(p.y, r[1], scale);
            expectRelativelyNear(p.z, r[2], scale);
        }
    }
    EXPECT_EQ(checked, cloud.size());
}

TEST(Unprojection, DegenerateIntrinsicsGiveNoCloudRatherThanGarbage) {
    frame::Frame frame;
    frame.cameraIntrinsics = {0.0, 0.0, 0.0, 0.0, 0, 0};
    frame.sceneDepth = frame::DepthData{frame::Plane<float>(4, 4, 1.0f), {}};
    EXPECT_TRUE(buildPointCloud(frame, frame::Confidence::Low, 0.0f).empty());
}

// A tilted wall n . p = offset seen through `k`: each pixel's depth is where its ray meets the wall.
struct TiltedWall {
    frame::Intrinsics k{100.0, 98.0, 59.5, 44.2, 120, 90};
    std::array<double, 3> n{0.2 / std::sqrt(1.05), -0.1 / std::sqrt(1.05), 1.0 / std::sqrt(1.05)};
    double offsetMeters = 1.5;

    frame::DepthData depth() const {
        frame::DepthData d{frame::Plane<float>(k.width, k.height),
                           frame::Plane<std::uint8_t>(k.width, k.height, 2)};
        for (int v = 0; v < k.height; ++v)
            for (int u = 0; u < k.width; ++u) {
                const double rx = (u - k.cx) / k.fx, ry = (v - k.cy) / k.fy;
                d.depthMeters.at(u, v) = static_cast<float>(offsetMeters / (n[0] * rx + n[1] * ry + n[2]));
            }
        return d;
    }
    double distanceMeters(const std::array<float, 3>& p) const {
        return n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - offsetMeters;
    }
    // The pixel whose ray `p` lies on, rounded.
    std::array<int, 2> pixelOf(const std::array<float, 3>& p) const {
        return {static_cast<int>(std::lround(k.fx * p[0] / p[2] + k.cx)),
                static_cast<int>(std::lround(k.fy * p[1] / p[2] + k.cy))};
    }
    // How far `p` is from the ray of pixel (u, v), in pixels.
    double pixelsFromRay(const std::array<float, 3>& p, int u, int v) const {
        return std::hypot(k.fx * p[0] / p[2] + k.cx - u, k.fy * p[1] / p[2] + k.cy - v);
    }
};

bool onBorder(const std::array<int, 2>& p, const Roi& r) {
    const bool inside = p[0] >= r.x && p[0] < r.x + r.width && p[1] >= r.y && p[1] < r.y + r.height;
    return inside && (p[0] == r.x || p[0] == r.x + r.width - 1 || p[1] == r.y || p[1] == r.y + r.height - 1);
}

TEST(RoiOutline, WalksEveryBorderPixelOnTheSurfaceFromTheTopLeftCornerClockwiseAndBack) {
    const TiltedWall wall;
    const frame::DepthData depth = wall.depth();
    const Roi roi{10, 8, 30, 20};
    const auto lines = roiOutline(depth, wall.k, roi, frame::Confidence::Low, 0.0f, 200);
    ASSERT_EQ(lines.size(), 1u);
    const Polyline3& line = lines[0];
    // 2 x 29 + 2 x 19 border pixels, fewer than 200: every one, and the first again to close the loop.
    ASSERT_EQ(line.size(), 97u);
    EXPECT_EQ(line.front(), line.back());
    std::set<std::array<int, 2>> seen;
    for (const auto& p : line) {
        EXPECT_NEAR(wall.distanceMeters(p), 0.0, 1e-5) << "on the wall";
        const std::array<int, 2> pixel = wall.pixelOf(p);
        EXPECT_LT(wall.pixelsFromRay(p, pixel[0], pixel[1]), 1e-3) << "on a pixel's ray";
        EXPECT_TRUE(onBorder(pixel, roi)) << pixel[0] << "," << pixel[1];
        seen.insert(pixel);
    }
    EXPECT_EQ(seen.size(), 96u);
    // Top row, right column, bottom row, left column: the corners at 0, 29, 29 + 19, 2 x 29 + 19.
    const std::array<std::pair<std::size_t, std::array<int, 2>>, 4> corners{
        {{0, {10, 8}}, {29, {39, 8}}, {48, {39, 27}}, {77, {10, 27}}}};
    for (const auto& [i, pixel] : corners)
        EXPECT_LT(wall.pixelsFromRay(line[i], pixel[0], pixel[1]), 1e-3) << "corner " << i;
    EXPECT_LT(wall.pixelsFromRay(line[1], 11, 8), 1e-3) << "along the top row first";
}

TEST(RoiOutline, ALongBorderIsSampledEvenlyWithItsCorners) {
    TiltedWall wall;
    wall.k = {500.0, 500.0, 319.5, 239.5, 640, 480};
    const frame::DepthData depth = wall.depth();
    const Roi roi{20, 30, 500, 400};
    const auto lines = roiOutline(depth, wall.k, roi, frame::Confidence::Low, 0.0f, 200);
    ASSERT_EQ(lines.size(), 1u);
    const Polyline3& line = lines[0];
    EXPECT_LE(line.size(), 205u) << "about 200, the corners and the closing vertex";
    EXPECT_GE(line.size(), 190u);
    for (const std::array<int, 2> corner : {std::array{20, 30}, {519, 30}, {519, 429}, {20, 429}})
        EXPECT_TRUE(
            std::any_of(line.begin(), line.end(),
                        [&](const auto& p) { return wall.pixelsFromRay(p, corner[0], corner[1]) < 1e-3; }))
            << corner[0] << "," << corner[1];
    for (std::size_t i = 0; i < line.size(); ++i) {
        EXPECT_NEAR(wall.distanceMeters(line[i]), 0.0, 1e-5);
        EXPECT_TRUE(onBorder(wall.pixelOf(line[i]), roi));
        if (i > 0) {
            const auto a = wall.pixelOf(line[i - 1]), b = wall.pixelOf(line[i]);
            const int apart = std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]);
            EXPECT_GE(apart, 1);
            EXPECT_LE(apart, 9) << "1796 border pixels in steps of at most ceil(1796 / 200)";
        }
    }
}

TEST(RoiOutline, SamplesTheCloudDoesNotDrawBreakTheOutline) {
    const TiltedWall wall;
    frame::DepthData depth = wall.depth();
    const Roi roi{10, 8, 30, 20};
    depth.depthMeters.at(20, 8) = 0.0f;                                     // top row: no measurement
    depth.depthMeters.at(10, 15) = std::numeric_limits<float>::quiet_NaN(); // left column
    depth.confidence.at(39, 20) = static_cast<std::uint8_t>(frame::Confidence::Low); // right column
    const auto ends = [&](const Polyline3& run) {
        return std::pair{wall.pixelOf(run.front()), wall.pixelOf(run.back())};
    };
    const auto low = roiOutline(depth, wall.k, roi, frame::Confidence::Low, 0.0f, 200);
    ASSERT_EQ(low.size(), 2u) << "the low-confidence sample is drawn at the lowest level";
    const auto medium = roiOutline(depth, wall.k, roi, frame::Confidence::Medium, 0.0f, 200);
    ASSERT_EQ(medium.size(), 3u);
    std::size_t vertices = 0;
    for (const Polyline3& run : medium) {
        vertices += run.size();
        for (const auto& p : run) {
            EXPECT_TRUE(std::isfinite(p[2]) && p[2] > 0.0f);
            EXPECT_NEAR(wall.distanceMeters(p), 0.0, 1e-5);
        }
    }
    EXPECT_EQ(vertices, 93u) << "every border pixel but the three, none twice";
    using Ends = std::pair<std::array<int, 2>, std::array<int, 2>>;
    EXPECT_EQ(ends(medium[0]), (Ends{{21, 8}, {39, 19}}));
    EXPECT_EQ(ends(medium[1]), (Ends{{39, 21}, {10, 16}}));
    EXPECT_EQ(ends(medium[2]), (Ends{{10, 14}, {19, 8}})) << "one run through the walk's first corner";

    // Nothing drawn past 1.6 m: the border's far part is gone, its near part kept.
    const auto near = roiOutline(wall.depth(), wall.k, roi, frame::Confidence::Low, 1.6f, 200);
    ASSERT_FALSE(near.empty()) << "the wall is nearer than 1.6 m at the region's right";
    for (const Polyline3& run : near)
        for (const auto& p : run)
            EXPECT_GE(p[2], 1.6f);
}

// A triangle region: the outline walks the pixels its edges pass through, each on the wall, within a pixel of
// an edge, the three corners' pixels among them, closed; at most the vertices asked for.
TEST(RoiOutline, APolygonRegionIsWalkedAlongItsEdges) {
    const TiltedWall wall;
    const frame::DepthData depth = wall.depth();
    const Polygon triangle{{10.5, 8.5}, {40.5, 8.5}, {10.5, 28.5}};
    const auto lines = roiOutline(depth, wall.k, triangle, frame::Confidence::Low, 0.0f, 200);
    ASSERT_EQ(lines.size(), 1u);
    const Polyline3& line = lines[0];
    EXPECT_EQ(line.front(), line.back());
    const auto distanceToEdge = [&](double x, double y) {
        double nearest = 1e9;
        for (std::size_t i = 0; i < triangle.size(); ++i) {
            const auto& a = triangle[i];
            const auto& b = triangle[(i + 1) % triangle.size()];
            const double dx = b[0] - a[0], dy = b[1] - a[1];
            const double t = std::clamp(((x - a[0]) * dx + (y - a[1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
            nearest = std::min(nearest, std::hypot(x - a[0] - t * dx, y - a[1] - t * dy));
        }
        return nearest;
    };
    for (const auto& p : line) {
        EXPECT_NEAR(wall.distanceMeters(p), 0.0, 1e-5) << "on the wall";
        const std::array<int, 2> pixel = wall.pixelOf(p);
        EXPECT_LE(distanceToEdge(pixel[0] + 0.5, pixel[1] + 0.5), 1.0) << pixel[0] << "," << pixel[1];
    }
    for (const std::array<int, 2> corner : {std::array{10, 8}, {40, 8}, {10, 28}})
        EXPECT_TRUE(
            std::any_of(line.begin(), line.end(), [&](const auto& p) { return wall.pixelOf(p) == corner; }))
            << corner[0] << "," << corner[1];
    const auto few = roiOutline(depth, wall.k, triangle, frame::Confidence::Low, 0.0f, 20);
    ASSERT_EQ(few.size(), 1u);
    EXPECT_LE(few[0].size(), 21u) << "20 vertices and the closing one";
    EXPECT_TRUE(
        roiOutline(depth, wall.k, Polygon{{1.0, 1.0}, {5.0, 5.0}}, frame::Confidence::Low, 0.0f, 200).empty())
        << "two vertices are no region";
}

TEST(RoiOutline, NothingForARegionOffTheMapOrInvalidIntrinsics) {
    const TiltedWall wall;
    const frame::DepthData depth = wall.depth();
    EXPECT_TRUE(roiOutline(depth, wall.k, {100, 8, 30, 20}, frame::Confidence::Low, 0.0f, 200).empty());
    EXPECT_TRUE(roiOutline(depth, wall.k, {10, 8, 0, 20}, frame::Confidence::Low, 0.0f, 200).empty());
    EXPECT_TRUE(roiOutline(depth, {}, {10, 8, 30, 20}, frame::Confidence::Low, 0.0f, 200).empty());
}

} // namespace
} // namespace dc::processing
