// No stage may output NaN or inf for any input, and large outputs keep their precision.

#include "processing/aura.h"
#include "processing/fog.h"
#include "processing/guided_filter.h"
#include "processing/pipeline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dc::processing {
namespace {

using frame::DepthData;
using frame::Plane;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

frame::FramePtr frameWith(DepthData depth, int cameraW, int cameraH, std::uint8_t luma = 90) {
    auto f = std::make_shared<frame::Frame>();
    const auto bytes = frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, cameraW, cameraH);
    auto nv12 = std::make_shared<std::vector<std::uint8_t>>(bytes, 128);
    for (int i = 0; i < cameraW * cameraH; ++i)
        (*nv12)[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(luma + (i * 7) % 50);
    f->capturedImage = {frame::PixelFormat::Nv12, cameraW, cameraH, std::move(nv12)};
    f->sceneDepth = std::move(depth);
    return f;
}

DepthData hostileDepth(int w, int h) {
    DepthData d{Plane<float>(w, h), Plane<std::uint8_t>(w, h, 2)};
    const float values[] = {kNaN, kInf, -kInf, -2.0f, 0.0f, 1e-4f, 1.5f, 1000.0f, 3.0f, 1e30f};
    for (std::size_t i = 0; i < d.depthMeters.pixels.size(); ++i)
        d.depthMeters.pixels[i] = values[(i * 3) % 10];
    return d;
}

void expectUsable(const DepthData& d) {
    for (float v : d.depthMeters.pixels)
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << v;
}

// Every stage's output (smoothing and upsampling of the shown map, fog, aura) for both shown maps and every
// upsampling method. The map that is not shown passes through unprocessed, as the source delivered it.
void runEverything(const frame::FramePtr& frame) {
    for (DepthSource source : {DepthSource::Smoothed, DepthSource::Raw})
        for (UpsamplingMethod method : {UpsamplingMethod::Full, UpsamplingMethod::Fast,
                                        UpsamplingMethod::Global, UpsamplingMethod::Quality}) {
            Pipeline pipeline = makeDefaultPipeline();
            ProcessingSettings settings;
            settings.smoothing = settings.upsampling = true;
            settings.depthSource = source;
            settings.upsamplingParams.method = method;
            for (int i = 0; i < 3; ++i) {
                auto f = std::make_shared<frame::Frame>(*frame);
                f->timestampNs = i * 16'000'000;
                const frame::FramePtr out = pipeline.run(f, settings, {});
                const DepthData* shown = shownDepth(*out, source);
                ASSERT_NE(shown, nullptr);
                expectUsable(*shown);
                EXPECT_EQ(showsSmoothed(*out, source), source == DepthSource::Smoothed);
                EXPECT_FALSE(renderFog(*out, {}, source).empty());
                EXPECT_FALSE(renderAura(*out, {}, source, i / 60.0).empty());
            }
        }
}

TEST(Numerics, HostileDepthNeverBecomesNonFiniteOutput) {
    runEverything(frameWith(hostileDepth(32, 24), 128, 96));
}

TEST(Numerics, AllInvalidFrame) {
    DepthData d{Plane<float>(32, 24, kNaN), Plane<std::uint8_t>(32, 24, 0)};
    runEverything(frameWith(d, 128, 96));
}

TEST(Numerics, OnePixelAndOneRowFrames) {
    runEverything(frameWith({Plane<float>(1, 1, 2.0f), {}}, 1, 1));
    runEverything(frameWith(hostileDepth(17, 1), 34, 1));
    runEverything(frameWith(hostileDepth(1, 17), 1, 34));
}

TEST(Numerics, SingleColourCameraImage) {
    auto f = std::make_shared<frame::Frame>(*frameWith(hostileDepth(32, 24), 128, 96));
    auto flat = std::make_shared<std::vector<std::uint8_t>>(*f->capturedImage.bytes);
    std::fill(flat->begin(), flat->begin() + 128 * 96, std::uint8_t{77});
    f->capturedImage.bytes = flat;
    runEverything(f);
}

// 8K output from a 480x270 map: a plane z = 1000 m + 1 mm per input pixel, single-colour guide. The guided
// filter of a plane is the plane (every window's mean is its centre's value), so every interior output pixel
// is known exactly; sums over millions of float values or E[z^2] - E[z]^2 at 1000 m would be far off.
TEST(Numerics, EightKOutputOfAKilometrePlaneStaysExact) {
    constexpr int kW = 480, kH = 270, kOutW = 7680, kOutH = 4320;
    DepthData d{Plane<float>(kW, kH), {}};
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            d.depthMeters.at(x, y) = 1000.0f + 0.001f * static_cast<float>(x);
    const std::vector<std::uint8_t> guide(static_cast<std::size_t>(kOutW) * kOutH, 100);
    for (int subsample : {1, 8}) {
        GuidedFilterParams p;
        p.radius = 16;
        p.subsample = subsample;
        const Plane<float> out =
            guidedUpsample(d, {guide.data(), kOutW, kOutH, kOutW}, kOutW, kOutH, p).depthMeters;
        double worst = 0.0;
        for (int y = 0; y < kOutH; y += 7)
            for (int x = 64; x < kOutW - 64; ++x) { // away from the borders, where windows are clipped
                const double sourceX = (x + 0.5) * kW / kOutW - 0.5;
                worst = std::max(worst, std::abs(out.at(x, y) - (1000.0 + 0.001 * sourceX)));
            }
        EXPECT_LT(worst, 1.3e-4) << "subsample " << subsample << " (float resolves 6.1e-5 m at 1000 m)";
    }
}

} // namespace
} // namespace dc::processing
