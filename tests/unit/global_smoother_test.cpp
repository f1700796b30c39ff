// The dual-guided global smoother against its double-precision reference (global_smoother_reference.h), on
// ordinary and stiff cases: constant depth, depths around 1e-4 m and 1e3 m, a 1000 m offset, non-finite and
// negative input, all invalid, 1x1, one row and one column, a smoothness reaching far beyond the image, a
// single-colour guide, 8K output, and low-confidence samples that must carry no weight.

#include "global_smoother_reference.h"

#include "processing/global_smoother.h"
#include "processing/upsampling_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dc::processing {
namespace {

using frame::Plane;

struct SmootherCase {
    frame::DepthData depth;
    std::vector<std::uint8_t> guide; // packed RGB, width x height
    int width = 0, height = 0;

    ColorView view() const { return {guide.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3}; }
};

// A colour guide with texture and an edge at x = width / 2, and a depth that slopes, steps at the same edge
// and carries noise, at the sensor's size.
SmootherCase texturedCase(int sensorWidth, int sensorHeight, int factor, double base, double variation,
                          std::uint64_t seed = 7) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    SmootherCase c{
        {Plane<float>(sensorWidth, sensorHeight), {}}, {}, sensorWidth * factor, sensorHeight * factor};
    c.guide.resize(static_cast<std::size_t>(c.width) * c.height * 3);
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const bool right = x >= c.width / 2;
            std::uint8_t* p = c.guide.data() + (static_cast<std::size_t>(y) * c.width + x) * 3;
            p[0] = static_cast<std::uint8_t>(right ? 200 : 40 + (x * 7 + y * 3) % 30);
            p[1] = static_cast<std::uint8_t>(right ? 60 : 120);
            p[2] = static_cast<std::uint8_t>(90 + (x / 3 + y / 2) % 2 * 8);
        }
    for (int y = 0; y < sensorHeight; ++y)
        for (int x = 0; x < sensorWidth; ++x) {
            const double edge = x >= sensorWidth / 2 ? -0.5 : 0.0;
            c.depth.depthMeters.at(x, y) =
                static_cast<float>(base + variation * (0.01 * x + edge + 0.02 * noise(rng)));
        }
    return c;
}

GlobalSmootherParams paramsFor(const SmootherCase& c, double noise, float smoothness = 1.0f) {
    UpsamplingParams up;
    up.method = UpsamplingMethod::Global;
    up.smoothness = smoothness;
    return globalSmootherParams(up, static_cast<double>(c.width) / c.depth.depthMeters.width,
                                static_cast<float>(noise));
}

Plane<float> run(const SmootherCase& c, const GlobalSmootherParams& p) {
    GlobalSmoother smoother;
    return smoother.upsample(c.depth, c.view(), p).depthMeters;
}

// Every output pixel finite, 0 exactly where the reference has no depth, and within `relative` of the
// reference elsewhere (and within `absolute`, when given).
void expectMatchesReference(const SmootherCase& c, const GlobalSmootherParams& p, double relative = 1e-4,
                            double absolute = std::numeric_limits<double>::infinity()) {
    const Plane<float> out = run(c, p);
    const Plane<double> ref = reference::upsample(c.depth, c.view(), p);
    ASSERT_EQ(out.pixels.size(), ref.pixels.size());
    for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(out.pixels[i])) << "pixel " << i;
        if (ref.pixels[i] == 0.0) {
            ASSERT_EQ(out.pixels[i], 0.0f) << "pixel " << i;
            continue;
        }
        const double error = std::abs(out.pixels[i] - ref.pixels[i]);
        ASSERT_LE(error, relative * std::abs(ref.pixels[i]))
            << "pixel " << i << " reference " << ref.pixels[i];
        ASSERT_LE(error, absolute) << "pixel " << i;
    }
}

TEST(GlobalSmoother, MatchesTheDoubleReferenceOnATexturedScene) {
    expectMatchesReference(texturedCase(40, 30, 3, 2.0, 0.3),
                           paramsFor(texturedCase(40, 30, 3, 2.0, 0.3), 0.005));
}

TEST(GlobalSmoother, MatchesTheReferenceWithConfidence) {
    SmootherCase c = texturedCase(32, 24, 4, 1.5, 0.3);
    c.depth.confidence = Plane<std::uint8_t>(32, 24);
    for (std::size_t i = 0; i < c.depth.confidence.pixels.size(); ++i)
        c.depth.confidence.pixels[i] = static_cast<std::uint8_t>((i * 7) % 3);
    expectMatchesReference(c, paramsFor(c, 0.005));
}

TEST(GlobalSmoother, QualityModeMatchesTheReference) {
    const SmootherCase c = texturedCase(24, 18, 4, 2.0, 0.3);
    UpsamplingParams up;
    up.method = UpsamplingMethod::Quality;
    expectMatchesReference(c, globalSmootherParams(up, 4.0, 0.005f));
}

TEST(GlobalSmoother, MatchesTheReferenceAtXEight) {
    const SmootherCase c = texturedCase(16, 12, 8, 2.0, 0.3);
    expectMatchesReference(c, paramsFor(c, 0.005));
}

// Buffers and per-thread scratch kept from one frame to the next must not carry anything over: after a
// first frame, a second, different one of the same size still matches the reference, on frames with many
// rows (run in pieces on the thread pool) and with one sensor row (whose every output row reads it).
TEST(GlobalSmoother, AReusedSmootherForgetsTheLastFrame) {
    for (const int rows : {30, 1}) {
        const SmootherCase first = texturedCase(40, rows, 3, 2.0, 0.3, 1);
        const SmootherCase second = texturedCase(40, rows, 3, 1.0, 0.5, 2);
        GlobalSmoother reused;
        reused.upsample(first.depth, first.view(), paramsFor(first, 0.005));
        const Plane<float> out =
            reused.upsample(second.depth, second.view(), paramsFor(second, 0.005)).depthMeters;
        const Plane<double> ref = reference::upsample(second.depth, second.view(), paramsFor(second, 0.005));
        ASSERT_EQ(out.pixels.size(), ref.pixels.size());
        for (std::size_t i = 0; i < ref.pixels.size(); ++i)
            ASSERT_NEAR(out.pixels[i], ref.pixels[i], 1e-4 * std::abs(ref.pixels[i]))
                << rows << " rows, pixel " << i;
    }
}

// A step of 0.5 m under a single-colour guide: interpolation and smoothing leave a ramp; the edge snap (the
// quality mode's last step) moves each pixel whose 3 x 3 neighbourhood spans the range to the nearer end,
// which steepens the ramp: fewer pixels are left in between.
TEST(GlobalSmoother, EdgeSnapSteepensABlurredStep) {
    SmootherCase c = texturedCase(20, 10, 4, 1.0, 0.0);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x)
            c.depth.depthMeters.at(x, y) = x < 10 ? 1.0f : 1.5f;
    std::fill(c.guide.begin(), c.guide.end(), std::uint8_t{128});
    const auto between = [](const Plane<float>& out) {
        return std::count_if(out.pixels.begin(), out.pixels.end(), [](float d) {
            return std::abs(d - 1.0f) > 1e-3f && std::abs(d - 1.5f) > 1e-3f;
        });
    };
    GlobalSmootherParams p = paramsFor(c, 0.005);
    const Plane<float> ramp = run(c, p);
    p.edgeSnapRange = 0.03f;
    const Plane<float> snapped = run(c, p);
    EXPECT_LT(between(snapped), between(ramp) * 3 / 4);
    expectMatchesReference(c, p);
}

TEST(GlobalSmoother, ConstantDepthStaysExactlyConstant) {
    SmootherCase c = texturedCase(33, 21, 3, 1.0, 0.0);
    for (float& d : c.depth.depthMeters.pixels)
        d = 1.2345f;
    for (float d : run(c, paramsFor(c, 0.005)).pixels)
        ASSERT_NEAR(d, 1.2345f, 2e-7f);
}

TEST(GlobalSmoother, TinyDepthsAroundATenthOfAMillimetre) {
    const SmootherCase c = texturedCase(30, 20, 3, 1e-4, 1e-5);
    expectMatchesReference(c, paramsFor(c, 1e-6));
}

TEST(GlobalSmoother, KilometreDepthsWithMillimetreVariation) {
    // Float resolves 1000 m to 6.1e-5 m: the result must stay within a few of those steps of the reference,
    // which needs the depths centred on their mean before any smoothing sums them.
    const SmootherCase c = texturedCase(30, 20, 3, 1000.0, 1e-3);
    expectMatchesReference(c, paramsFor(c, 1e-5), 1e-4, 2.5e-4);
}

TEST(GlobalSmoother, AThousandMetreOffsetOnlyShiftsTheResult) {
    const SmootherCase near = texturedCase(30, 20, 3, 1.5, 0.2);
    SmootherCase far = near;
    for (float& d : far.depth.depthMeters.pixels)
        d += 1000.0f;
    const Plane<float> a = run(near, paramsFor(near, 0.005)), b = run(far, paramsFor(far, 0.005));
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        ASSERT_NEAR(b.pixels[i] - 1000.0, a.pixels[i], 2.5e-4) << "pixel " << i;
}

TEST(GlobalSmoother, NonFiniteAndNegativeDepthIsNeverAnOutput) {
    SmootherCase c = texturedCase(25, 19, 3, 2.0, 0.3);
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                         std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(),
                         -1.0f,
                         0.0f,
                         -0.0f};
    for (std::size_t i = 0; i < c.depth.depthMeters.pixels.size(); i += 7)
        c.depth.depthMeters.pixels[i] = bad[(i / 7) % 6];
    const Plane<float> out = run(c, paramsFor(c, 0.005));
    std::size_t holes = 0;
    for (float d : out.pixels) {
        ASSERT_TRUE(std::isfinite(d));
        ASSERT_TRUE(d == 0.0f || d > 1.5f) << d << ": a hole is never averaged in as 0 m";
        holes += d == 0.0f;
    }
    EXPECT_GT(holes, 0u) << "pixels next to a hole whose bilinear weight is below one half stay holes";
    expectMatchesReference(c, paramsFor(c, 0.005));
}

TEST(GlobalSmoother, AllInvalidGivesAllZero) {
    SmootherCase c = texturedCase(12, 9, 2, 2.0, 0.3);
    for (std::size_t i = 0; i < c.depth.depthMeters.pixels.size(); ++i)
        c.depth.depthMeters.pixels[i] = i % 2 ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
    for (float d : run(c, paramsFor(c, 0.005)).pixels)
        ASSERT_EQ(d, 0.0f);
}

TEST(GlobalSmoother, OnePixelKeepsItsDepth) {
    SmootherCase c = texturedCase(1, 1, 1, 2.5, 0.0);
    c.depth.depthMeters.pixels[0] = 2.5f;
    EXPECT_FLOAT_EQ(run(c, paramsFor(c, 0.005)).pixels[0], 2.5f);
    SmootherCase wide = texturedCase(1, 1, 5, 2.5, 0.0);
    wide.depth.depthMeters.pixels[0] = 2.5f;
    for (float d : run(wide, paramsFor(wide, 0.005)).pixels)
        ASSERT_FLOAT_EQ(d, 2.5f);
}

TEST(GlobalSmoother, OneRowAndOneColumn) {
    for (const auto& [w, h] : {std::pair{17, 1}, std::pair{1, 17}}) {
        SmootherCase c = texturedCase(w, h, 3, 2.0, 0.3);
        expectMatchesReference(c, paramsFor(c, 0.005));
    }
}

TEST(GlobalSmoother, SmoothnessReachingFarBeyondTheImage) {
    const SmootherCase c = texturedCase(9, 6, 3, 2.0, 0.3);
    expectMatchesReference(c, paramsFor(c, 0.005, 1e4f));
}

TEST(GlobalSmoother, SingleColourGuide) {
    SmootherCase c = texturedCase(30, 20, 3, 2.0, 0.3);
    std::fill(c.guide.begin(), c.guide.end(), std::uint8_t{97});
    expectMatchesReference(c, paramsFor(c, 0.005));
}

TEST(GlobalSmoother, LowConfidenceSamplesCarryNoWeight) {
    SmootherCase c = texturedCase(40, 30, 2, 2.0, 0.0);
    c.depth.confidence = Plane<std::uint8_t>(40, 30, 2);
    for (int y = 10; y < 14; ++y)
        for (int x = 5; x < 9; ++x) { // far outliers, flagged low confidence, on the guide's left surface
            c.depth.depthMeters.at(x, y) = 3.0f;
            c.depth.confidence.at(x, y) = 0;
        }
    const Plane<float> out = run(c, paramsFor(c, 0.005));
    for (int y = 20; y < 28; ++y)
        for (int x = 10; x < 18; ++x)
            EXPECT_NEAR(out.at(x, y), 2.0f, 1e-3f) << "the outliers are filled in from their neighbours";
}

// 8K output from a 480x270 map of a plane z = 1000 m + 1 mm per input pixel under a single-colour guide:
// every pass preserves a plane away from the borders, so the interior is known exactly, where float sums
// over 33 million pixels or uncentred depths at 1000 m would be far off.
TEST(GlobalSmoother, EightKOutputOfAKilometrePlaneStaysExact) {
    constexpr int kW = 480, kH = 270, kOutW = 7680, kOutH = 4320;
    SmootherCase c{{Plane<float>(kW, kH), {}},
                   std::vector<std::uint8_t>(static_cast<std::size_t>(kOutW) * kOutH * 3, 100),
                   kOutW,
                   kOutH};
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            c.depth.depthMeters.at(x, y) = 1000.0f + 0.001f * static_cast<float>(x);
    const Plane<float> out = run(c, paramsFor(c, 0.005));
    double worst = 0.0;
    for (int y = 0; y < kOutH; y += 7)
        for (int x = 2048; x < kOutW - 2048; ++x) { // away from the borders, where the smoothing is one-sided
            const double sourceX = (x + 0.5) * kW / kOutW - 0.5;
            worst = std::max(worst, std::abs(out.at(x, y) - (1000.0 + 0.001 * sourceX)));
        }
    EXPECT_LT(worst, 1.3e-4) << "float resolves 6.1e-5 m at 1000 m";
}

} // namespace
} // namespace dc::processing
