#include "processing/point_accumulator.h"

#include "devices/synthetic_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

namespace dc::processing {
namespace {

// A w x h frame of a flat wall at `depth` meters with an all-High confidence, a gray image and `pose`.
devices::Frame wallFrame(int w, int h, float depth, const devices::Pose& pose) {
    devices::Frame f;
    f.cameraIntrinsics = {100.0, 100.0, w / 2.0, h / 2.0, w, h};
    f.sceneDepth =
        devices::DepthData{devices::Plane<float>(w, h, depth), devices::Plane<std::uint8_t>(w, h, 2)};
    f.capturedImage = {
        devices::PixelFormat::Rgb24, w, h,
        std::make_shared<const std::vector<std::uint8_t>>(static_cast<std::size_t>(w) * h * 3, 128)};
    f.pose = pose;
    return f;
}

devices::Pose translated(double x, double y, double z) {
    devices::Pose p;
    p.cameraToWorld[12] = x;
    p.cameraToWorld[13] = y;
    p.cameraToWorld[14] = z;
    return p;
}

TEST(PointAccumulator, PointsLandInWorldCoordinatesThroughThePose) {
    PointAccumulator acc(1000, 0.001f);
    const devices::Frame f = wallFrame(4, 4, 2.0f, translated(1.0, -2.0, 3.0));
    ASSERT_EQ(acc.add(f, devices::Confidence::Low, 0.0f), 16u);
    // Pixel (0, 0): camera point ((0 - 2) * 2 / 100, (0 - 2) * 2 / 100, 2), then translated.
    const WorldPoint& p = acc.slots()[0];
    EXPECT_NEAR(p.x, 1.0 - 0.04, 1e-6);
    EXPECT_NEAR(p.y, -2.0 - 0.04, 1e-6);
    EXPECT_NEAR(p.z, 5.0, 1e-6);
    EXPECT_EQ(p.rgba & 0xffu, 128u);
}

TEST(PointAccumulator, AFrameWithoutPoseAddsNothing) {
    PointAccumulator acc(100);
    devices::Frame f = wallFrame(4, 4, 1.0f, {});
    f.pose.reset();
    EXPECT_EQ(acc.add(f, devices::Confidence::Low, 0.0f), 0u);
    EXPECT_EQ(acc.size(), 0u);
}

TEST(PointAccumulator, ThePointsOfAVoxelAlreadyHeldAreNotAddedAgain) {
    PointAccumulator acc(1000, 0.01f);
    const devices::Frame f = wallFrame(8, 8, 1.0f, {});
    const std::size_t first = acc.add(f, devices::Confidence::Low, 0.0f);
    EXPECT_GT(first, 0u);
    EXPECT_EQ(acc.add(f, devices::Confidence::Low, 0.0f), 0u) << "the same view adds no copies";
    // Samples 1 cm apart at 1 m with a 1 cm voxel: each lands in its own voxel.
    EXPECT_EQ(first, 64u);
}

TEST(PointAccumulator, TheOldestPointsLeaveFirstWhenTheBudgetIsFull) {
    PointAccumulator acc(40, 0.001f);
    for (int i = 0; i < 5; ++i)
        acc.add(wallFrame(4, 4, 1.0f, translated(i, 0, 0)), devices::Confidence::Low, 0.0f);
    EXPECT_EQ(acc.size(), 40u);
    std::set<int> frames;
    for (const WorldPoint& p : acc.slots())
        frames.insert(static_cast<int>(std::lround(p.x)));
    EXPECT_EQ(frames, (std::set<int>{2, 3, 4})) << "80 points went in, the first 40 left";
    // An evicted voxel can be filled again: the hash forgot it when its slot was reused.
    EXPECT_EQ(acc.add(wallFrame(4, 4, 1.0f, translated(0, 0, 0)), devices::Confidence::Low, 0.0f), 16u);
}

TEST(PointAccumulator, HashStaysConsistentUnderHeavyChurn) {
    PointAccumulator acc(500, 0.002f);
    for (int i = 0; i < 200; ++i) {
        const double s = 0.003 * i;
        acc.add(wallFrame(16, 12, 1.0f + 0.001f * static_cast<float>(i % 7), translated(s, -s, 0)),
                devices::Confidence::Low, 0.0f);
    }
    ASSERT_EQ(acc.size(), 500u);
    // No two held points share a voxel.
    std::set<std::tuple<long, long, long>> voxels;
    for (const WorldPoint& p : acc.slots())
        voxels.emplace(std::lround(std::floor(p.x / 0.002f)), std::lround(std::floor(p.y / 0.002f)),
                       std::lround(std::floor(p.z / 0.002f)));
    EXPECT_EQ(voxels.size(), 500u);
}

TEST(PointAccumulator, DirtyRangesCoverExactlyTheNewSlots) {
    PointAccumulator acc(20, 0.001f);
    acc.add(wallFrame(4, 4, 1.0f, translated(0, 0, 0)), devices::Confidence::Low, 0.0f);
    auto dirty = acc.takeDirty();
    ASSERT_EQ(dirty.size(), 1u);
    EXPECT_EQ(dirty[0], (std::pair<std::size_t, std::size_t>{0, 16}));
    acc.add(wallFrame(4, 4, 1.0f, translated(1, 0, 0)), devices::Confidence::Low, 0.0f);
    dirty = acc.takeDirty();
    ASSERT_EQ(dirty.size(), 2u) << "the ring wrapped";
    EXPECT_EQ(dirty[0], (std::pair<std::size_t, std::size_t>{16, 20}));
    EXPECT_EQ(dirty[1], (std::pair<std::size_t, std::size_t>{0, 12}));
    EXPECT_TRUE(acc.takeDirty().empty());
    const auto generation = acc.generation();
    acc.clear();
    EXPECT_EQ(acc.size(), 0u);
    EXPECT_GT(acc.generation(), generation);
}

TEST(PointAccumulator, InvalidAndFilteredSamplesAreSkipped) {
    PointAccumulator acc(100, 0.001f);
    devices::Frame f = wallFrame(4, 4, 1.0f, {});
    auto& d = f.sceneDepth->depthMeters;
    d.at(0, 0) = std::nanf("");
    d.at(1, 0) = -1.0f;
    d.at(2, 0) = 0.0f;
    d.at(3, 0) = std::numeric_limits<float>::infinity();
    f.sceneDepth->confidence.at(0, 1) = 0;
    EXPECT_EQ(acc.add(f, devices::Confidence::Medium, 0.0f), 11u);
}

} // namespace
} // namespace dc::processing
