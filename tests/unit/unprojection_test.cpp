#include "devices/synthetic/synthetic_device.h"
#include "processing/point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>

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

} // namespace
} // namespace dc::processing
