// The masked guided filter against a double-precision, brute-force reference on the stiff cases: constant
// images, depths around 1e-4 m and 1e3 m, a 1000 m offset, non-finite and negative input, degenerate sizes,
// a radius beyond the image, a single-colour guide.

#include "guided_filter_reference.h"

#include "processing/guided_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dc::processing {
namespace {

using frame::Plane;

struct GuidedCase {
    Plane<float> guide, depth, weight;
};

// A textured guide in [0, 1] and a depth that follows it in places and jumps at an edge, plus noise.
GuidedCase texturedCase(int w, int h, double base, double variation, std::uint64_t seed = 7) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    GuidedCase c{Plane<float>(w, h), Plane<float>(w, h), Plane<float>(w, h, 1.0f)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double g = 0.5 + 0.3 * std::sin(0.7 * x) * std::cos(0.4 * y) + 0.1 * unit(rng);
            c.guide.at(x, y) = static_cast<float>(g);
            const double edge = x > w / 2 ? 1.0 : 0.0;
            c.depth.at(x, y) = static_cast<float>(base + variation * (0.5 * g + edge + 0.2 * unit(rng)));
        }
    return c;
}

GuidedFilterParams params(int radius, double depthScale) {
    GuidedFilterParams p;
    p.radius = radius;
    p.epsilon = 1e-3f;
    p.fitNoise = static_cast<float>(0.01 * depthScale);
    return p;
}

// Every output pixel within `tolerance` of the reference, and finite.
void expectMatchesReference(const GuidedCase& c, const GuidedFilterParams& p, double tolerance) {
    const Plane<float> out = maskedGuidedFilter(c.guide, c.depth, c.weight, p);
    const std::vector<double> ref = reference::filter(c.guide, c.depth, c.weight, p);
    ASSERT_EQ(out.pixels.size(), ref.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        ASSERT_TRUE(std::isfinite(out.pixels[i])) << "pixel " << i;
        worst = std::max(worst, std::abs(out.pixels[i] - ref[i]));
    }
    EXPECT_LE(worst, tolerance);
}

TEST(GuidedFilter, MatchesTheDoubleReferenceOnATexturedScene) {
    for (bool fitWeighted : {false, true}) {
        GuidedFilterParams p = params(3, 1.0);
        p.fitWeighted = fitWeighted;
        expectMatchesReference(texturedCase(40, 30, 2.0, 0.3), p, 5e-7);
    }
}

TEST(GuidedFilter, ConstantDepthStaysExactlyConstant) {
    GuidedCase c = texturedCase(33, 21, 1.0, 0.0);
    for (float& d : c.depth.pixels)
        d = 1.2345f;
    const Plane<float> out = maskedGuidedFilter(c.guide, c.depth, c.weight, params(4, 1.0));
    for (float d : out.pixels)
        EXPECT_NEAR(d, 1.2345f, 1e-6f);
}

TEST(GuidedFilter, TinyDepthsAroundATenthOfAMillimetre) {
    expectMatchesReference(texturedCase(30, 20, 1e-4, 1e-5), params(3, 1e-5), 1.5e-11);
}

TEST(GuidedFilter, KilometreDepthsWithMillimetreVariation) {
    // Float resolves 1000 m to 6e-5 m; the filter must not lose more than a few of those steps, where
    // one-pass float statistics (E[z^2] - E[z]^2 ~ 1e6 - 1e6) would lose all of the millimetres.
    expectMatchesReference(texturedCase(30, 20, 1000.0, 1e-3), params(3, 1e-3), 1.25e-4);
}

TEST(GuidedFilter, AThousandMetreOffsetOnlyShiftsTheResult) {
    const GuidedCase near = texturedCase(30, 20, 1.5, 0.2);
    GuidedCase far = near;
    for (float& d : far.depth.pixels)
        d += 1000.0f;
    const GuidedFilterParams p = params(3, 0.2);
    const Plane<float> a = maskedGuidedFilter(near.guide, near.depth, near.weight, p);
    const Plane<float> b = maskedGuidedFilter(far.guide, far.depth, far.weight, p);
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        ASSERT_NEAR(b.pixels[i] - 1000.0, a.pixels[i], 1.25e-4) << "pixel " << i;
    expectMatchesReference(far, p, 1.25e-4);
}

TEST(GuidedFilter, NonFiniteAndNegativeDepthIsAHoleNeverAnOutput) {
    GuidedCase c = texturedCase(25, 19, 2.0, 0.3);
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                         std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(),
                         -1.0f,
                         0.0f,
                         -0.0f};
    for (std::size_t i = 0; i < c.depth.pixels.size(); i += 7)
        c.depth.pixels[i] = bad[(i / 7) % 6];
    const Plane<float> out = maskedGuidedFilter(c.guide, c.depth, c.weight, params(3, 0.3));
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(out.pixels[i]));
        if (i % 7 == 0)
            EXPECT_EQ(out.pixels[i], 0.0f) << "a hole stays a hole";
        else
            EXPECT_GT(out.pixels[i], 1.5f) << "holes are not averaged in as 0 m";
    }
    expectMatchesReference(c, params(3, 0.3), 5e-7);
}

TEST(GuidedFilter, AllInvalidGivesAllZero) {
    GuidedCase c = texturedCase(12, 9, 2.0, 0.3);
    for (std::size_t i = 0; i < c.depth.pixels.size(); ++i)
        c.depth.pixels[i] = i % 2 ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
    for (float d : maskedGuidedFilter(c.guide, c.depth, c.weight, params(2, 1.0)).pixels)
        EXPECT_EQ(d, 0.0f);
}

TEST(GuidedFilter, OnePixelImageKeepsItsDepth) {
    const GuidedCase c{Plane<float>(1, 1, 0.3f), Plane<float>(1, 1, 2.5f), Plane<float>(1, 1, 1.0f)};
    EXPECT_FLOAT_EQ(maskedGuidedFilter(c.guide, c.depth, c.weight, params(5, 1.0)).pixels[0], 2.5f);
}

TEST(GuidedFilter, OneRowAndOneColumnImages) {
    expectMatchesReference(texturedCase(57, 1, 2.0, 0.3), params(4, 0.3), 5e-7);
    expectMatchesReference(texturedCase(1, 57, 2.0, 0.3), params(4, 0.3), 5e-7);
}

TEST(GuidedFilter, RadiusLargerThanTheImage) {
    expectMatchesReference(texturedCase(9, 6, 2.0, 0.3), params(50, 0.3), 5e-7);
}

TEST(GuidedFilter, SingleColourGuideAveragesDepth) {
    GuidedCase c = texturedCase(30, 20, 2.0, 0.3);
    for (float& g : c.guide.pixels)
        g = 0.42f; // variance exactly 0: a = cov / epsilon = 0, no division by zero
    expectMatchesReference(c, params(3, 0.3), 5e-7);
}

TEST(GuidedFilter, FractionalWeightsFromInterpolation) {
    GuidedCase c = texturedCase(30, 20, 2.0, 0.3);
    for (std::size_t i = 0; i < c.weight.pixels.size(); ++i)
        c.weight.pixels[i] = static_cast<float>((i * 37 % 11) / 10.0);
    expectMatchesReference(c, params(3, 0.3), 5e-7);
}

} // namespace
} // namespace dc::processing
