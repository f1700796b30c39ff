#include "processing/confidence_filter.h"

#include <gtest/gtest.h>

#include <limits>

namespace dc::processing {
namespace {

using frame::Confidence;

frame::DepthData sample() {
    frame::DepthData d{frame::Plane<float>(6, 1), frame::Plane<std::uint8_t>(6, 1)};
    d.depthMeters.pixels = {1.0f, 1.5f, 2.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 0.05f};
    d.confidence.pixels = {0, 1, 2, 2, 2, 2};
    return d;
}

TEST(ConfidenceFilter, KeepsOnlySamplesAtOrAboveTheLevel) {
    const frame::DepthData d = sample();
    EXPECT_EQ(filterByConfidence(d, Confidence::Low).pixels,
              (std::vector<float>{1.0f, 1.5f, 2.0f, 0, 0, 0.05f}));
    EXPECT_EQ(filterByConfidence(d, Confidence::Medium).pixels,
              (std::vector<float>{0, 1.5f, 2.0f, 0, 0, 0.05f}));
    EXPECT_EQ(filterByConfidence(d, Confidence::High).pixels, (std::vector<float>{0, 0, 2.0f, 0, 0, 0.05f}));
}

TEST(ConfidenceFilter, CountsDrawablePointsWithTheNearLimit) {
    const frame::DepthData d = sample();
    EXPECT_EQ(countDrawablePoints(d, Confidence::Low, 0.0f), 4u);
    EXPECT_EQ(countDrawablePoints(d, Confidence::Low, 0.1f), 3u) << "0.05 m is nearer than the limit";
    EXPECT_EQ(countDrawablePoints(d, Confidence::High, 0.1f), 1u);
}

TEST(ConfidenceFilter, WithoutAConfidenceMapEveryValidSampleIsKept) {
    frame::DepthData d = sample();
    d.confidence = {};
    EXPECT_EQ(countDrawablePoints(d, Confidence::High, 0.0f), 4u);
}

TEST(ConfidenceFilter, InvalidDepthNeverSurvives) {
    frame::DepthData d{frame::Plane<float>(3, 1), frame::Plane<std::uint8_t>(3, 1, 2)};
    d.depthMeters.pixels = {-1.0f, std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity()};
    EXPECT_EQ(countDrawablePoints(d, Confidence::Low, 0.0f), 0u);
    for (float v : filterByConfidence(d, Confidence::Low).pixels)
        EXPECT_EQ(v, 0.0f);
}

} // namespace
} // namespace dc::processing
