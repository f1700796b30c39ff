#include "processing/accumulation_worker.h"
#include "processing/point_colours.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

namespace dc::processing {
namespace {

// A w x h wall `depth` meters in front of a camera at `x` meters along the world's x axis.
frame::FramePtr wallAt(double x, float depth, int w = 16, int h = 12) {
    auto f = std::make_shared<frame::Frame>();
    f->cameraIntrinsics = {20.0, 20.0, w / 2.0, h / 2.0, w, h};
    f->sceneDepth = frame::DepthData{frame::Plane<float>(w, h, depth), frame::Plane<std::uint8_t>(w, h, 2)};
    f->capturedImage = {
        frame::PixelFormat::Rgb24, w, h,
        std::make_shared<const std::vector<std::uint8_t>>(static_cast<std::size_t>(w) * h * 3, 90)};
    frame::Pose pose;
    pose.cameraToWorld[12] = x;
    f->pose = pose;
    return f;
}

// The request the frame processor makes of a frame shown raw: its depth and the colours of its points.
AccumulationWorker::Request requestFor(const frame::FramePtr& frame, std::size_t budget = 1000) {
    const auto& d = frame->sceneDepth->depthMeters;
    return {std::shared_ptr<const frame::DepthData>(frame, &*frame->sceneDepth),
            frame->depthIntrinsics(),
            std::make_shared<const RgbImage>(pointColours(frame->capturedImage, d.width, d.height)),
            *frame->pose,
            frame::Confidence::Low,
            0.0f,
            budget,
            0.001f};
}

TEST(AccumulationWorker, AddsExactlyWhatTheAccumulatorItselfWouldAdd) {
    AccumulationWorker worker;
    PointAccumulator direct(1000, 0.001f);
    for (int i = 0; i < 5; ++i) {
        const frame::FramePtr frame = wallAt(0.5 * i, 1.0f + 0.1f * static_cast<float>(i));
        worker.submit(requestFor(frame));
        worker.waitIdle();
        direct.add(*frame, frame::Confidence::Low, 0.0f);
    }
    EXPECT_EQ(worker.size(), direct.size());
    EXPECT_EQ(worker.size(), 5u * 16 * 12);
    std::vector<WorldPoint> read;
    ASSERT_TRUE(worker.tryRead([&](PointAccumulator& points) { read = points.slots(); }))
        << "an idle worker lets the render thread read";
    ASSERT_EQ(read.size(), direct.slots().size());
    for (std::size_t i = 0; i < read.size(); ++i) {
        EXPECT_EQ(read[i].x, direct.slots()[i].x) << i;
        EXPECT_EQ(read[i].z, direct.slots()[i].z) << i;
        EXPECT_EQ(read[i].rgba, direct.slots()[i].rgba) << i;
    }
}

TEST(AccumulationWorker, ABudgetChangeReachesTheWorkerAndClearEmptiesIt) {
    AccumulationWorker worker;
    const auto handedOver = std::chrono::steady_clock::now();
    worker.submit(requestFor(wallAt(0.0, 1.0f), 100));
    worker.waitIdle();
    const double windowMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - handedOver).count();
    EXPECT_EQ(worker.size(), 100u) << "only the budget is kept";
    // The add happened between the hand-over and waitIdle's return: its time, in milliseconds, lies
    // within that window (a stale, unset or wrongly scaled figure does not).
    EXPECT_GT(worker.lastAddMilliseconds(), 0.0);
    EXPECT_LE(worker.lastAddMilliseconds(), windowMs);
    worker.clear();
    EXPECT_EQ(worker.size(), 0u);
    worker.waitIdle();
    EXPECT_EQ(worker.size(), 0u);
}

TEST(AccumulationWorker, FramesHandedOverFasterThanAddedAreSkippedNotQueued) {
    AccumulationWorker worker;
    constexpr int kFrames = 200;
    for (int i = 0; i < kFrames; ++i)
        // Each wall 2 mm behind the last: no voxel is shared, so every frame added adds all its points.
        worker.submit(requestFor(wallAt(0.0, 2.0f + 0.002f * static_cast<float>(i), 64, 48), 1'000'000));
    worker.waitIdle();
    const std::uint64_t added = worker.size() / (64 * 48);
    EXPECT_EQ(added + worker.skipped(), static_cast<std::uint64_t>(kFrames))
        << "every frame was either added or counted as skipped";
    EXPECT_GE(added, 1u) << "the newest frame is always added";
}

// Two sources handing frames over faster than they are added: each has its own latest-wins slot, served in
// turn, so that the second source's frames are added however many the first hands over, and every frame
// is still added or counted as skipped.
TEST(AccumulationWorker, EachSourceHasItsOwnSlotAndTheyAreServedInTurn) {
    AccumulationWorker worker;
    constexpr int kFrames = 150;
    for (int i = 0; i < kFrames; ++i) {
        const float depth = 2.0f + 0.002f * static_cast<float>(i);
        worker.submit(requestFor(wallAt(0.0, depth, 64, 48), 2'000'000), 0);
        worker.submit(requestFor(wallAt(10.0, depth, 64, 48), 2'000'000), 1); // 10 m away: its own points
    }
    worker.waitIdle();
    std::size_t first = 0, second = 0;
    ASSERT_TRUE(worker.tryRead([&](PointAccumulator& points) {
        for (std::size_t i = 0; i < points.size(); ++i)
            ++(points.slots()[i].x > 5.0f ? second : first);
    }));
    const std::uint64_t added = worker.size() / (64 * 48);
    EXPECT_EQ(added + worker.skipped(), 2u * kFrames) << "every frame was either added or counted as skipped";
    EXPECT_GE(second, 64u * 48) << "the second source's newest frame is always added";
    EXPECT_GE(first, 64u * 48);
    // In turn: neither source has more than one frame more added than the other.
    EXPECT_LE(std::max(first, second) - std::min(first, second), 64u * 48) << first << " and " << second;
}

} // namespace
} // namespace dc::processing
