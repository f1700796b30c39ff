#include "processing/aura.h"
#include "processing/fog.h"

#include <gtest/gtest.h>

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

TEST(AuraMatte, NearestRegionIsTheNearestConnectedSurface) {
    DepthData d = squareScene(40, 30, 10, 8, 10);
    d.depthMeters.at(35, 25) = 0.1f; // one stray sample nearer than the subject
    const Plane<std::uint8_t> matte = subjectMatte(d, {});
    std::size_t inside = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            const bool square = x >= 10 && x < 20 && y >= 8 && y < 18;
            EXPECT_EQ(matte.at(x, y), square ? 1 : 0) << x << "," << y;
            inside += matte.at(x, y);
        }
    EXPECT_EQ(inside, 100u);
}

TEST(AuraMatte, NearestRegionFollowsASlopeButNotAJump) {
    DepthData d = constantDepth(40, 30, 3.0f);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 20; ++x)
            d.depthMeters.at(x, y) = 0.5f + 0.01f * x; // a surface receding 1 cm per pixel
    const Plane<std::uint8_t> matte = subjectMatte(d, {});
    EXPECT_EQ(matte.at(19, 15), 1);
    EXPECT_EQ(matte.at(20, 15), 0);
}

TEST(AuraMatte, NearRangeSelectsByDistance) {
    AuraSettings s;
    s.matte = AuraMatte::NearRange;
    s.nearMeters = 1.5f;
    s.farMeters = 3.0f;
    const Plane<std::uint8_t> matte = subjectMatte(squareScene(40, 30, 10, 8, 10), s);
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
