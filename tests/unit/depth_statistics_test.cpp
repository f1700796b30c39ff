// The automatic depth range from a histogram: within one bin of the sorted percentiles, invalid samples
// ignored, extreme depths kept finite and in order.

#include "processing/depth_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace dc::processing {
namespace {

frame::Plane<float> planeOf(const std::vector<float>& values) {
    frame::Plane<float> plane(static_cast<int>(values.size()), 1);
    plane.pixels = values;
    return plane;
}

// The sample of rank floor(q (n - 1)) among the valid ones, by sorting.
float sortedQuantile(std::vector<float> values, double q) {
    std::erase_if(values, [](float d) { return !(d > 0.0f) || !std::isfinite(d); });
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

// A bin is 1/1024 of the depth wide: the histogram's answer is the lower edge of the sorted answer's bin.
void expectWithinOneBin(float histogram, float sorted) {
    EXPECT_LE(histogram, sorted);
    EXPECT_LT(sorted - histogram, sorted / 1024.0f + 1e-7f)
        << "histogram " << histogram << ", sorted " << sorted;
}

TEST(DepthHistogram, PercentilesAreWithinOneBinOfTheSortedOnes) {
    std::mt19937 random(7);
    for (const auto& [low, high] : {std::pair{0.2f, 0.6f}, std::pair{0.5f, 4.0f}, std::pair{1.0f, 80.0f}}) {
        std::uniform_real_distribution<float> depth(low, high);
        std::vector<float> values(50000);
        for (float& v : values)
            v = depth(random);
        // A tenth of the samples invalid, as a sensor's holes are: 0, NaN, infinity, negative.
        for (std::size_t i = 0; i < values.size(); i += 10)
            values[i] = std::array{0.0f, std::numeric_limits<float>::quiet_NaN(),
                                   std::numeric_limits<float>::infinity(), -1.0f}[(i / 10) % 4];
        const frame::Plane<float> plane = planeOf(values);
        const auto range = percentileRange(plane);
        ASSERT_TRUE(range.has_value());
        expectWithinOneBin(range->minMeters, sortedQuantile(values, 0.02));
        expectWithinOneBin(range->maxMeters, sortedQuantile(values, 0.98));
        expectWithinOneBin(medianDepth(plane), sortedQuantile(values, 0.5));
    }
}

TEST(DepthHistogram, NoValidSampleGivesNoRangeAndTheDefaultPivot) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const frame::Plane<float> invalid = planeOf({0.0f, nan, -2.0f, std::numeric_limits<float>::infinity()});
    EXPECT_FALSE(percentileRange(invalid).has_value());
    EXPECT_EQ(medianDepth(invalid), 1.0f);
    EXPECT_FALSE(percentileRange(frame::Plane<float>()).has_value());
}

TEST(DepthHistogram, OneDepthGivesARangeOneCentimetreWide) {
    const auto range = percentileRange(planeOf(std::vector<float>(1000, 1.5f)));
    ASSERT_TRUE(range.has_value());
    expectWithinOneBin(range->minMeters, 1.5f);
    EXPECT_NEAR(range->maxMeters - range->minMeters, 0.01f, 1e-6f);
}

// Depths far outside any sensor's reach (a micrometre, a thousand kilometres, the largest float) count in
// the end bins: the range stays finite, ordered, and inside the histogram's span.
TEST(DepthHistogram, ExtremeDepthsGiveAFiniteOrderedRange) {
    std::vector<float> values(1000, 1e-6f);
    values.resize(2000, 1e6f);
    values.push_back(std::numeric_limits<float>::max());
    values.push_back(std::numeric_limits<float>::denorm_min());
    const auto range = percentileRange(planeOf(values));
    ASSERT_TRUE(range.has_value());
    EXPECT_TRUE(std::isfinite(range->minMeters) && std::isfinite(range->maxMeters));
    EXPECT_GE(range->minMeters, DepthHistogram::kLowestMeters);
    EXPECT_LE(range->maxMeters, DepthHistogram::kHighestMeters);
    EXPECT_LT(range->minMeters, range->maxMeters);
}

// A frame too large to count whole is subsampled, and its percentiles still land within a few bins.
TEST(DepthHistogram, ALargeFrameIsSubsampledAndStaysClose) {
    frame::Plane<float> plane(1280, 720);
    for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x)
            plane.at(x, y) = 0.5f + 3.0f * static_cast<float>(y * plane.width + x) / (1280.0f * 720.0f);
    const auto range = percentileRange(plane);
    ASSERT_TRUE(range.has_value());
    EXPECT_NEAR(range->minMeters, sortedQuantile(plane.pixels, 0.02), 0.01f);
    EXPECT_NEAR(range->maxMeters, sortedQuantile(plane.pixels, 0.98), 0.01f);
}

} // namespace
} // namespace dc::processing
