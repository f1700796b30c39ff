#include "processing/confidence_estimator.h"

#include <gtest/gtest.h>

namespace dc::processing {
namespace {

using frame::Confidence;
using frame::Plane;

constexpr auto kLow = static_cast<std::uint8_t>(Confidence::Low);
constexpr auto kMedium = static_cast<std::uint8_t>(Confidence::Medium);
constexpr auto kHigh = static_cast<std::uint8_t>(Confidence::High);

// A gently slanted wall 2 m away: what a good depth sensor sees.
Plane<float> wall(int w = 16, int h = 12) {
    Plane<float> p(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            p.at(x, y) = 2.0f + 0.002f * static_cast<float>(x);
    return p;
}

TEST(ConfidenceEstimator, ASmoothSurfaceIsHighEverywhereEvenAtTheBorder) {
    const Plane<std::uint8_t> c = estimateConfidence(wall(), nullptr);
    for (std::uint8_t v : c.pixels)
        ASSERT_EQ(v, kHigh);
}

TEST(ConfidenceEstimator, HolesAndTheirNeighboursAreLowered) {
    Plane<float> d = wall();
    d.at(5, 5) = 0.0f;            // one hole: neighbours have 1 invalid neighbour -> medium
    for (int x = 10; x < 13; ++x) // a hole of three: the pixel between them has 3 invalid -> low
        d.at(x, 3) = 0.0f;
    const Plane<std::uint8_t> c = estimateConfidence(d, nullptr);
    EXPECT_EQ(c.at(5, 5), kLow) << "no measurement";
    EXPECT_EQ(c.at(4, 5), kMedium);
    EXPECT_EQ(c.at(11, 4), kLow);
    EXPECT_EQ(c.at(0, 11), kHigh) << "far from any hole";
}

TEST(ConfidenceEstimator, ADepthEdgeIsLow) {
    Plane<float> d = wall();
    for (int y = 0; y < d.height; ++y)
        for (int x = 8; x < d.width; ++x)
            d.at(x, y) = 3.0f; // a 1 m step: flying pixels live here
    const Plane<std::uint8_t> c = estimateConfidence(d, nullptr);
    EXPECT_EQ(c.at(7, 5), kLow);
    EXPECT_EQ(c.at(8, 5), kLow);
    EXPECT_EQ(c.at(2, 5), kHigh);
    EXPECT_EQ(c.at(13, 5), kHigh);
}

// Tall enough to be split into bands that run in parallel: every row still sees its true neighbours, so
// exactly the rows next to each horizontal depth step are low, wherever the bands happen to be cut.
TEST(ConfidenceEstimator, RowsNextToStepsAreLowWhereverTheImageIsSplit) {
    constexpr int kStep = 25;
    Plane<float> d = wall(16, 401);
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x)
            d.at(x, y) += static_cast<float>(y / kStep % 2); // 2 m and 3 m bands
    const Plane<std::uint8_t> c = estimateConfidence(d, nullptr);
    for (int y = 0; y < d.height; ++y) {
        const bool nextToStep = (y % kStep == 0 && y > 0) || (y % kStep == kStep - 1 && y + 1 < d.height);
        for (int x = 0; x < d.width; ++x)
            ASSERT_EQ(c.at(x, y), nextToStep ? kLow : kHigh) << x << "," << y;
    }
}

TEST(ConfidenceEstimator, NoiseAtLargeDepthIsJudgedRelativeToTheDepth) {
    Plane<float> d(8, 8, 9.0f);
    for (int i = 0; i < 64; i += 2)
        d.pixels[static_cast<std::size_t>(i)] = 9.0f + 0.045f; // +-0.25 %: fine at 9 m
    EXPECT_EQ(estimateConfidence(d, nullptr).at(4, 4), kHigh);
    for (int i = 0; i < 64; i += 2)
        d.pixels[static_cast<std::size_t>(i)] = 9.0f + 0.9f; // 10 % jumps: noise
    EXPECT_EQ(estimateConfidence(d, nullptr).at(4, 4), kLow);
}

TEST(ConfidenceEstimator, TemporalJumpsLowerConfidence) {
    const Plane<float> before = wall();
    Plane<float> now = wall();
    now.at(3, 3) *= 1.03f; // a 3 % jump: at best medium
    now.at(9, 9) *= 1.2f;  // 20 %: low
    const Plane<std::uint8_t> c = estimateConfidence(now, &before);
    EXPECT_EQ(c.at(9, 9), kLow);
    EXPECT_LE(c.at(3, 3), kMedium);
    EXPECT_EQ(c.at(12, 2), kHigh);
    Plane<float> steady(16, 12, 2.0f);
    Plane<float> moved(16, 12, 2.07f); // the whole scene 3.5 % further: every pixel only medium
    EXPECT_EQ(estimateConfidence(moved, &steady).at(8, 6), kMedium);
    EXPECT_EQ(estimateConfidence(moved, nullptr).at(8, 6), kHigh) << "no previous frame: not counted";
}

frame::FramePtr frameWith(Plane<float> depth, Plane<std::uint8_t> confidence = {}) {
    auto f = std::make_shared<frame::Frame>();
    f->sceneDepth = frame::DepthData{std::move(depth), std::move(confidence)};
    return f;
}

TEST(ConfidenceEstimatorStage, FillsMissingConfidenceLabelledEstimatedAndLeavesSensorConfidence) {
    ConfidenceEstimatorStage stage;
    EXPECT_TRUE(stage.wanted({}, {}));
    EXPECT_FALSE(stage.wanted({}, {.confidence = false})) << "nothing reads confidence";
    const frame::FramePtr out = stage.process(frameWith(wall()), {});
    ASSERT_EQ(out->sceneDepth->confidence.width, 16);
    EXPECT_TRUE(out->sceneDepth->confidenceEstimated);
    const frame::FramePtr sensor = frameWith(wall(), Plane<std::uint8_t>(16, 12, kLow));
    EXPECT_EQ(stage.process(sensor, {}), sensor) << "sensor confidence passes untouched";
    EXPECT_FALSE(sensor->sceneDepth->confidenceEstimated);
}

TEST(ConfidenceEstimatorStage, ARedoOfTheSameFrameComparesWithTheSameFrameBefore) {
    ConfidenceEstimatorStage stage;
    auto first = std::make_shared<frame::Frame>(*frameWith(wall()));
    first->timestampNs = 1;
    stage.process(first, {});
    Plane<float> moved = wall();
    for (float& d : moved.pixels)
        d += 0.2f; // a jump against the previous frame: Low everywhere the change counts
    auto second = std::make_shared<frame::Frame>(*frameWith(moved));
    second->timestampNs = 2;
    const auto once = stage.process(second, {})->sceneDepth->confidence;
    const auto again = stage.process(second, {})->sceneDepth->confidence;
    EXPECT_EQ(again.pixels, once.pixels) << "the redo must not compare the frame with itself";
    EXPECT_NE(once.pixels, estimateConfidence(moved, nullptr).pixels) << "the frame before counted";
}

TEST(ConfidenceEstimatorStage, IsInTheDefaultPipeline) {
    EXPECT_TRUE(makeDefaultPipeline().hasStage(kConfidenceEstimateStage));
}

} // namespace
} // namespace dc::processing
