#include "devices/synthetic/synthetic_device.h"
#include "processing/aura.h"
#include "processing/fog.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dc::processing {
namespace {

using frame::DepthData;
using frame::Plane;

frame::FramePtr solidFrame(int cameraW, int cameraH, std::array<std::uint8_t, 3> rgb, DepthData depth) {
    auto f = std::make_shared<frame::Frame>();
    std::vector<std::uint8_t> bytes;
    for (int i = 0; i < cameraW * cameraH; ++i)
        bytes.insert(bytes.end(), rgb.begin(), rgb.end());
    f->capturedImage = {frame::PixelFormat::Rgb24, cameraW, cameraH,
                        std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
    f->sceneDepth = std::move(depth);
    return f;
}

DepthData constantDepth(int w, int h, float meters, std::uint8_t confidence = 2) {
    return {Plane<float>(w, h, meters), Plane<std::uint8_t>(w, h, confidence)};
}

std::array<int, 3> pixel(const RgbaImage& image, int x, int y) {
    const std::uint8_t* p = image.pixels.data() + (static_cast<std::size_t>(y) * image.width + x) * 4;
    return {p[0], p[1], p[2]};
}

constexpr std::array<std::uint8_t, 3> kCamera{100, 150, 200};

void expectColor(std::array<int, 3> got, std::array<double, 3> want) {
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(got[k], want[k], 1.01) << "channel " << k;
}

std::array<double, 3> mixed(std::array<double, 3> a, std::array<double, 3> b, double t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}

const std::array<double, 3> kCameraD{100, 150, 200};

std::array<double, 3> fogColor(const FogSettings& s) {
    return {s.color[0] * 255.0, s.color[1] * 255.0, s.color[2] * 255.0};
}

TEST(Fog, MixesTheFogColorInProportionToDistance) {
    const FogSettings s; // fogMax 4 m
    const RgbaImage half =
        renderFog(*solidFrame(64, 48, kCamera, constantDepth(16, 12, 2.0f)), s, DepthSource::Raw);
    ASSERT_EQ(half.width, 32) << "half the camera size";
    ASSERT_EQ(half.height, 24);
    expectColor(pixel(half, 10, 10), mixed(kCameraD, fogColor(s), 0.5));
    EXPECT_EQ(half.pixels[3], 255);
    const RgbaImage far =
        renderFog(*solidFrame(64, 48, kCamera, constantDepth(16, 12, 9.0f)), s, DepthSource::Raw);
    expectColor(pixel(far, 5, 20), fogColor(s)); // clamped at 1
}

TEST(Fog, PixelsWithoutMeasurementAreBeyondRangeNotAtZeroMetres) {
    DepthData d = constantDepth(64, 12, 2.0f);
    for (int y = 0; y < 12; ++y)
        for (int x = 32; x < 64; ++x)
            d.depthMeters.at(x, y) = (x + y) % 2 ? 0.0f : std::numeric_limits<float>::quiet_NaN();
    const FogSettings s;
    const RgbaImage out = renderFog(*solidFrame(256, 48, kCamera, d), s, DepthSource::Raw);
    expectColor(pixel(out, 20, 12), mixed(kCameraD, fogColor(s), 0.5)); // 2 m, far from the holes
    const std::array<int, 3> edge = pixel(out, 62, 12);                 // 2 m, next to the holes
    EXPECT_GT(edge[0], 149 + 5) << "more fog next to the holes, never less";
    expectColor(pixel(out, 127, 12), fogColor(s));
}

TEST(Fog, ConfidenceOverlayTintsLowConfidenceRed) {
    FogSettings s;
    s.confidenceOverlay = true;
    const auto at = [&](std::uint8_t confidence) {
        return pixel(renderFog(*solidFrame(64, 48, kCamera, constantDepth(16, 12, 2.0f, confidence)), s,
                               DepthSource::Raw),
                     16, 12);
    };
    const std::array<double, 3> fogged = mixed(kCameraD, fogColor(s), 0.5), red{255, 0, 0};
    expectColor(at(0), red);
    expectColor(at(1), mixed(red, fogged, 0.5));
    expectColor(at(2), fogged);
}

TEST(Fog, UsesTheSelectedDepthAndNeedsAnImage) {
    auto f = std::make_shared<frame::Frame>(*solidFrame(64, 48, kCamera, constantDepth(16, 12, 9.0f)));
    f->smoothedSceneDepth = constantDepth(16, 12, 0.0001f);
    expectColor(pixel(renderFog(*f, {}, DepthSource::Smoothed), 3, 3), kCameraD);
    expectColor(pixel(renderFog(*f, {}, DepthSource::Raw), 3, 3), fogColor({}));
    f->sceneDepth.reset();
    f->smoothedSceneDepth.reset();
    expectColor(pixel(renderFog(*f, {}, DepthSource::Raw), 3, 3), kCameraD); // no depth: no fog
    f->capturedImage = {};
    EXPECT_TRUE(renderFog(*f, {}, DepthSource::Raw).empty());
}

// A square subject at 0.5 m in front of a 2 m background.
DepthData squareScene(int w, int h, int x0, int y0, int side) {
    DepthData d = constantDepth(w, h, 2.0f);
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x)
            d.depthMeters.at(x, y) = 0.5f;
    return d;
}

// Without intrinsics (as these synthetic maps) a 40-pixel-wide map spans a 60 degree field of view: a pixel
// is 1.4 cm across at 0.5 m.
TEST(AuraMatte, NearestRegionIsTheNearestRegionThatStandsOut) {
    DepthData d = squareScene(40, 30, 10, 8, 10);
    for (int y = 24; y < 26; ++y) // a 6 mm speck nearer than the subject: too small to be one
        for (int x = 30; x < 32; ++x)
            d.depthMeters.at(x, y) = 0.1f;
    const Plane<std::uint8_t> matte = subjectMatte(d, {}, {});
    std::size_t inside = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            const bool square = x >= 10 && x < 20 && y >= 8 && y < 18;
            EXPECT_EQ(matte.at(x, y), square ? 1 : 0) << x << "," << y;
            inside += matte.at(x, y);
        }
    EXPECT_EQ(inside, 100u);
    AuraSettings smallSubjects;
    smallSubjects.minSizeMeters = 0.005f;
    EXPECT_EQ(subjectMatte(d, {}, smallSubjects).at(30, 24), 1) << "the speck, once small subjects count";
}

// A floor receding from the camera, 1 cm per row, nearest at the image's bottom edge.
DepthData floorScene(int w, int h) {
    DepthData d = constantDepth(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            d.depthMeters.at(x, y) = 1.0f + 0.01f * static_cast<float>(h - 1 - y);
    return d;
}

// A box standing on the floor, its front face `standsOutMeters` nearer than the floor at its bottom row.
void placeBox(DepthData& d, int x0, int y0, int side, float standsOutMeters) {
    const float front = d.depthMeters.at(x0, y0 + side - 1) - standsOutMeters;
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x)
            d.depthMeters.at(x, y) = front;
}

TEST(AuraMatte, TheFloorIsNoSubjectAndALowStepIsNone) {
    DepthData d = floorScene(60, 40);
    const Plane<std::uint8_t> bare = subjectMatte(d, {}, {});
    EXPECT_EQ(std::count(bare.pixels.begin(), bare.pixels.end(), 1), 0)
        << "the floor is nearest at the border: it continues out of view";
    placeBox(d, 8, 22, 8, 0.015f); // a book: it rises 0.5 cm above the floor just in front of it
    placeBox(d, 40, 10, 8, 0.10f); // farther, but it stands 9 cm in front of the floor before it
    const Plane<std::uint8_t> matte = subjectMatte(d, {}, {});
    EXPECT_EQ(matte.at(44, 14), 1);
    EXPECT_EQ(matte.at(12, 26), 0);
    EXPECT_EQ(matte.at(44, 25), 0) << "the floor in front of the box";
    EXPECT_EQ(std::count(matte.pixels.begin(), matte.pixels.end(), 1), 64);
}

// Projects a world point into the depth map of `frame` (OpenCV axes, as frame::Pose).
std::array<double, 3> project(const frame::Frame& f, const double world[3]) {
    const auto& m = f.pose->cameraToWorld;
    const double p[3] = {world[0] - m[12], world[1] - m[13], world[2] - m[14]};
    double c[3];
    for (int axis = 0; axis < 3; ++axis) // the rotation's transpose: columns of m are the camera's axes
        c[axis] = m[axis * 4] * p[0] + m[axis * 4 + 1] * p[1] + m[axis * 4 + 2] * p[2];
    const frame::Intrinsics k = f.depthIntrinsics();
    return {k.fx * c[0] / c[2] + k.cx, k.fy * c[1] / c[2] + k.cy, c[2]};
}

// The issue this answers: on the built-in scene the ring went round the desk's far side. The subject must
// be the apple (not the desk, not the book lying on it), from every viewpoint of the moving camera.
TEST(AuraMatte, TheSyntheticScenesSubjectIsTheApple) {
    devices::SyntheticConfig config;
    config.motion = true;
    config.paced = false;
    config.cameraWidth = 640; // the image is not looked at; a small one is quick to render
    config.cameraHeight = 480;
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open().ok());
    for (double t : {0.0, 2.5, 7.5}) {
        const frame::FramePtr f = device.makeFrame(1, t);
        const Plane<std::uint8_t> matte = subjectMatte(*f->sceneDepth, f->depthIntrinsics(), {});
        const auto [u, v, z] = project(*f, devices::scene::kAppleCenter);
        const double radiusPixels = devices::scene::kAppleRadius * f->depthIntrinsics().fx / z;
        // The silhouette of a sphere off the optical axis is a slightly larger ellipse; its edge pixels mix
        // apple and desk. The book and the desk lie tens of pixels away.
        const double tolerance = 1.2;
        std::size_t inside = 0, outside = 0;
        for (int y = 0; y < matte.height; ++y)
            for (int x = 0; x < matte.width; ++x)
                if (matte.at(x, y))
                    ++(std::hypot(x + 0.5 - u, y + 0.5 - v) <= tolerance * radiusPixels + 2.0 ? inside
                                                                                              : outside);
        const double discPixels = 3.14159265358979323846 * radiusPixels * radiusPixels;
        EXPECT_EQ(outside, 0u) << "t = " << t;
        EXPECT_GT(static_cast<double>(inside), 0.6 * discPixels) << "t = " << t;
    }
}

TEST(AuraMatte, NearRangeSelectsByDistance) {
    AuraSettings s;
    s.matte = AuraMatte::NearRange;
    s.nearMeters = 1.5f;
    s.farMeters = 3.0f;
    const Plane<std::uint8_t> matte = subjectMatte(squareScene(40, 30, 10, 8, 10), {}, s);
    EXPECT_EQ(matte.at(15, 12), 0);
    EXPECT_EQ(matte.at(2, 2), 1);
}

int brightness(std::array<int, 3> c) {
    return c[0] + c[1] + c[2];
}

TEST(Aura, GlowsYellowAroundTheSubjectAndPulses) {
    const auto frame = solidFrame(640, 480, {40, 40, 40}, squareScene(160, 120, 60, 40, 40));
    const RgbaImage a = renderAura(*frame, {}, DepthSource::Raw, 0.0);
    ASSERT_EQ(a.width, 320);
    ASSERT_EQ(a.height, 240);
    // The subject covers output pixels 120..199 x 80..159; its ring lies just outside.
    const std::array<int, 3> ring = pixel(a, 115, 120), farAway = pixel(a, 5, 235);
    EXPECT_GT(brightness(ring), brightness(farAway) + 60);
    EXPECT_GT(ring[0], ring[2] + 20) << "yellow: red and green gain more than blue";
    EXPECT_EQ(ring[0], ring[1]);
    const RgbaImage later = renderAura(*frame, {}, DepthSource::Raw, 0.25 / AuraSettings{}.pulseHz);
    EXPECT_NE(pixel(later, 115, 120), ring) << "the glow's size oscillates";
}

TEST(Aura, WithoutDepthIsTheCameraImage) {
    auto f = std::make_shared<frame::Frame>(*solidFrame(64, 48, kCamera, constantDepth(16, 12, 1.0f)));
    f->sceneDepth.reset();
    expectColor(pixel(renderAura(*f, {}, DepthSource::Raw, 1.0), 10, 10), kCameraD);
}

} // namespace
} // namespace dc::processing
