#include "processing/point_accumulator.h"
#include "processing/point_colours.h"

#include "devices/synthetic/synthetic_scene.h"
#include "frame/color.h"
#include "processing/confidence_filter.h"
#include "processing/point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <tuple>

namespace dc::processing {
namespace {

// A w x h frame of a flat wall at `depth` meters with an all-High confidence, a gray image and `pose`.
frame::Frame wallFrame(int w, int h, float depth, const frame::Pose& pose) {
    frame::Frame f;
    f.cameraIntrinsics = {100.0, 100.0, w / 2.0, h / 2.0, w, h};
    f.sceneDepth = frame::DepthData{frame::Plane<float>(w, h, depth), frame::Plane<std::uint8_t>(w, h, 2)};
    f.capturedImage = {
        frame::PixelFormat::Rgb24, w, h,
        std::make_shared<const std::vector<std::uint8_t>>(static_cast<std::size_t>(w) * h * 3, 128)};
    f.pose = pose;
    return f;
}

frame::Pose translated(double x, double y, double z) {
    frame::Pose p;
    p.cameraToWorld[12] = x;
    p.cameraToWorld[13] = y;
    p.cameraToWorld[14] = z;
    return p;
}

TEST(PointAccumulator, PointsLandInWorldCoordinatesThroughThePose) {
    PointAccumulator acc(1000, 0.001f);
    const frame::Frame f = wallFrame(4, 4, 2.0f, translated(1.0, -2.0, 3.0));
    ASSERT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 16u);
    // Pixel (0, 0): camera point ((0 - 2) * 2 / 100, (0 - 2) * 2 / 100, 2), then translated.
    const WorldPoint& p = acc.slots()[0];
    EXPECT_NEAR(p.x, 1.0 - 0.04, 1e-6);
    EXPECT_NEAR(p.y, -2.0 - 0.04, 1e-6);
    EXPECT_NEAR(p.z, 5.0, 1e-6);
    EXPECT_EQ(p.rgba & 0xffu, 128u);
}

TEST(PointAccumulator, AFrameWithoutPoseAddsNothing) {
    PointAccumulator acc(100);
    frame::Frame f = wallFrame(4, 4, 1.0f, {});
    f.pose.reset();
    EXPECT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 0u);
    EXPECT_EQ(acc.size(), 0u);
}

TEST(PointAccumulator, ThePointsOfAVoxelAlreadyHeldAreNotAddedAgain) {
    PointAccumulator acc(1000, 0.01f);
    const frame::Frame f = wallFrame(8, 8, 1.0f, {});
    const std::size_t first = acc.add(f, frame::Confidence::Low, 0.0f);
    EXPECT_GT(first, 0u);
    EXPECT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 0u) << "the same view adds no copies";
    // Samples 1 cm apart at 1 m with a 1 cm voxel: each lands in its own voxel.
    EXPECT_EQ(first, 64u);
}

TEST(PointAccumulator, TheOldestPointsLeaveFirstWhenTheBudgetIsFull) {
    PointAccumulator acc(40, 0.001f);
    for (int i = 0; i < 5; ++i)
        acc.add(wallFrame(4, 4, 1.0f, translated(i, 0, 0)), frame::Confidence::Low, 0.0f);
    EXPECT_EQ(acc.size(), 40u);
    std::set<int> frames;
    for (const WorldPoint& p : acc.slots())
        frames.insert(static_cast<int>(std::lround(p.x)));
    EXPECT_EQ(frames, (std::set<int>{2, 3, 4})) << "80 points went in, the first 40 left";
    // An evicted voxel can be filled again: the hash forgot it when its slot was reused.
    EXPECT_EQ(acc.add(wallFrame(4, 4, 1.0f, translated(0, 0, 0)), frame::Confidence::Low, 0.0f), 16u);
}

TEST(PointAccumulator, HashStaysConsistentUnderHeavyChurn) {
    PointAccumulator acc(500, 0.002f);
    for (int i = 0; i < 200; ++i) {
        const double s = 0.003 * i;
        acc.add(wallFrame(16, 12, 1.0f + 0.001f * static_cast<float>(i % 7), translated(s, -s, 0)),
                frame::Confidence::Low, 0.0f);
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
    acc.add(wallFrame(4, 4, 1.0f, translated(0, 0, 0)), frame::Confidence::Low, 0.0f);
    auto dirty = acc.takeDirty();
    ASSERT_EQ(dirty.size(), 1u);
    EXPECT_EQ(dirty[0], (std::pair<std::size_t, std::size_t>{0, 16}));
    acc.add(wallFrame(4, 4, 1.0f, translated(1, 0, 0)), frame::Confidence::Low, 0.0f);
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
    frame::Frame f = wallFrame(4, 4, 1.0f, {});
    auto& d = f.sceneDepth->depthMeters;
    d.at(0, 0) = std::nanf("");
    d.at(1, 0) = -1.0f;
    d.at(2, 0) = 0.0f;
    d.at(3, 0) = std::numeric_limits<float>::infinity();
    f.sceneDepth->confidence.at(0, 1) = 0;
    EXPECT_EQ(acc.add(f, frame::Confidence::Medium, 0.0f), 11u);
}

// A w x h frame translated by (tx, ty, tz) whose depth is random in [0.5, 1.5) m with some invalid samples
// and a random confidence per sample.
frame::Frame randomFrame(int w, int h, std::mt19937& rng, double tx, double ty, double tz) {
    frame::Frame f = wallFrame(w, h, 1.0f, translated(tx, ty, tz));
    std::uniform_real_distribution<float> depth(0.5f, 1.5f);
    std::uniform_int_distribution<int> level(0, 2), invalid(0, 19);
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            f.sceneDepth->depthMeters.at(u, v) = invalid(rng) == 0 ? std::nanf("") : depth(rng);
            f.sceneDepth->confidence.at(u, v) = static_cast<std::uint8_t>(level(rng));
        }
    }
    return f;
}

using Voxel = std::tuple<long, long, long>;

Voxel voxelOf(float x, float y, float z, float voxelMeters) {
    return {std::lround(std::floor(x / voxelMeters)), std::lround(std::floor(y / voxelMeters)),
            std::lround(std::floor(z / voxelMeters))};
}

// The accumulate rule written as plainly as possible, for frames whose pose is a pure translation (the
// world point is then the camera point plus the translation, exactly as the float transform computes it).
class ReferenceAccumulator {
public:
    ReferenceAccumulator(std::size_t budget, float voxelMeters) : ring_(budget), voxelMeters_(voxelMeters) {}

    std::size_t add(const frame::Frame& f, frame::Confidence minLevel, float nearMeters) {
        const frame::DepthData& d = *f.sceneDepth;
        const frame::Intrinsics k = f.depthIntrinsics();
        const auto t = [&](int i) {
            return static_cast<float>(f.pose->cameraToWorld[static_cast<std::size_t>(12 + i)]);
        };
        std::size_t added = 0;
        for (int v = 0; v < d.depthMeters.height; ++v) {
            for (int u = 0; u < d.depthMeters.width; ++u) {
                if (!keepSample(d.depthMeters.at(u, v), d.confidence.at(u, v), minLevel, nearMeters))
                    continue;
                const auto [x, y, z] = unproject(u, v, d.depthMeters.at(u, v), k);
                const Voxel voxel = voxelOf(x + t(0), y + t(1), z + t(2), voxelMeters_);
                if (held_.count(voxel))
                    continue;
                if (count_ == ring_.size())
                    held_.erase(ring_[next_]);
                held_.insert(voxel);
                ring_[next_] = voxel;
                next_ = (next_ + 1) % ring_.size();
                count_ = std::min(count_ + 1, ring_.size());
                ++added;
            }
        }
        return added;
    }
    const std::vector<Voxel>& ring() const { return ring_; }

private:
    std::vector<Voxel> ring_;
    std::set<Voxel> held_;
    float voxelMeters_;
    std::size_t next_ = 0, count_ = 0;
};

// Runs `frames` random frames through both and checks every count and every slot's voxel.
void expectSameAsReference(std::size_t budget, float voxelMeters, int w, int h, int frames, double drift) {
    PointAccumulator acc(budget, voxelMeters);
    ReferenceAccumulator ref(budget, voxelMeters);
    std::mt19937 rng(7);
    for (int i = 0; i < frames; ++i) {
        const double s = drift * (i % 5);
        const frame::Frame f = randomFrame(w, h, rng, s, -s, 0.0);
        ASSERT_EQ(acc.add(f, frame::Confidence::Medium, 0.6f), ref.add(f, frame::Confidence::Medium, 0.6f))
            << "frame " << i;
        for (std::size_t slot = 0; slot < acc.size(); ++slot) {
            const WorldPoint& p = acc.slots()[slot];
            ASSERT_EQ(voxelOf(p.x, p.y, p.z, voxelMeters), ref.ring()[slot])
                << "frame " << i << " slot " << slot;
        }
    }
}

TEST(PointAccumulator, MatchesThePlainRuleUnderChurnAndRevisits) {
    // Coarse voxels and a small budget: many duplicates, evictions, and voxels freed then filled again.
    expectSameAsReference(3000, 0.02f, 48, 36, 40, 0.01);
}

TEST(PointAccumulator, MatchesThePlainRuleWhileItsTablesGrow) {
    // A fine voxel over many samples: the block table grows several times, then the ring churns.
    expectSameAsReference(60'000, 0.001f, 160, 120, 6, 0.0);
}

TEST(PointAccumulator, AVoxelFreedByEvictionCanBeOccupiedAgain) {
    PointAccumulator acc(16, 0.001f);
    const frame::Frame a = wallFrame(4, 4, 1.0f, translated(0, 0, 0));
    ASSERT_EQ(acc.add(a, frame::Confidence::Low, 0.0f), 16u);
    EXPECT_EQ(acc.add(a, frame::Confidence::Low, 0.0f), 0u) << "all held";
    // A far-away frame evicts every point of the first, so their voxels (and blocks) are free again.
    ASSERT_EQ(acc.add(wallFrame(4, 4, 1.0f, translated(10, 0, 0)), frame::Confidence::Low, 0.0f), 16u);
    EXPECT_EQ(acc.add(a, frame::Confidence::Low, 0.0f), 16u);
    EXPECT_EQ(acc.add(a, frame::Confidence::Low, 0.0f), 0u) << "held again, so de-duplicated again";
}

TEST(PointAccumulator, PointsLandAtTheirWorldPositionThroughARotation) {
    // Camera turned 90 degrees about the world y axis: camera +z looks along world +x, camera +x is world -z.
    frame::Pose pose;
    pose.cameraToWorld = {0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0.5, 0.25, -1, 1};
    PointAccumulator acc(100, 0.001f);
    ASSERT_EQ(acc.add(wallFrame(4, 4, 2.0f, pose), frame::Confidence::Low, 0.0f), 16u);
    // Pixel (3, 1): camera point ((3 - 2) * 2 / 100, (1 - 2) * 2 / 100, 2) = (0.02, -0.02, 2).
    const WorldPoint& p = acc.slots()[1 * 4 + 3];
    EXPECT_NEAR(p.x, 0.5 + 2.0, 1e-6);
    EXPECT_NEAR(p.y, 0.25 - 0.02, 1e-6);
    EXPECT_NEAR(p.z, -1.0 - 0.02, 1e-6);
}

TEST(PointAccumulator, ClearAndConfigureForgetTheHeldVoxels) {
    PointAccumulator acc(100, 0.001f);
    const frame::Frame f = wallFrame(4, 4, 1.0f, {});
    ASSERT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 16u);
    acc.clear();
    EXPECT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 16u);
    acc.configure(50, 0.001f);
    EXPECT_EQ(acc.size(), 0u);
    EXPECT_EQ(acc.budget(), 50u);
    EXPECT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 16u);
    acc.configure(50, 0.5f);
    EXPECT_EQ(acc.add(wallFrame(4, 4, 1.0f, translated(0.25, 0.25, 0)), frame::Confidence::Low, 0.0f), 1u)
        << "the 4 cm wall fits one 50 cm voxel";
}

TEST(PointAccumulator, SamplesNearerThanTheNearLimitAreSkipped) {
    PointAccumulator acc(100, 0.001f);
    frame::Frame f = wallFrame(4, 4, 1.0f, {});
    f.sceneDepth->depthMeters.at(0, 0) = 0.2f;
    f.sceneDepth->depthMeters.at(1, 0) = 0.29f;
    EXPECT_EQ(acc.add(f, frame::Confidence::Low, 0.3f), 14u);
}

// An image of random bytes in `format`.
frame::CapturedImage randomImage(frame::PixelFormat format, int w, int h, std::mt19937& rng) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(format, w, h));
    std::uniform_int_distribution<int> byte(0, 255);
    for (auto& b : bytes)
        b = static_cast<std::uint8_t>(byte(rng));
    return {format, w, h, std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
}

std::uint32_t packedPixelRgb(const frame::CapturedImage& image, int x, int y) {
    const frame::Rgb c = frame::pixelRgb(image, x, y);
    return static_cast<std::uint32_t>(frame::toByte(c.r)) |
           static_cast<std::uint32_t>(frame::toByte(c.g)) << 8 |
           static_cast<std::uint32_t>(frame::toByte(c.b)) << 16 | 0xff000000u;
}

TEST(CameraColourTable, GivesExactlyWhatPixelRgbGivesInEveryFormat) {
    std::mt19937 rng(3);
    CameraColourTable table;
    for (const auto format :
         {frame::PixelFormat::Nv12, frame::PixelFormat::Yuyv, frame::PixelFormat::Rgb24}) {
        const frame::CapturedImage image = randomImage(format, 61, 47, rng);
        ASSERT_TRUE(table.use(image));
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                ASSERT_EQ(table.rgba(x, y), packedPixelRgb(image, x, y))
                    << frame::toString(format) << " pixel " << x << ", " << y;
    }
}

TEST(CameraColourTable, GivesExactlyWhatPixelRgbGivesForEveryYCbCrTriplet) {
    // YUYV, 256 pairs a row and a row per Cb: pair (cr, cb) holds lumas l and l + 128, so 128 images cover
    // all 2^24 triplets, the rounding of every channel at every value included.
    CameraColourTable table;
    constexpr int kPairs = 256, kRows = 256;
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(std::size_t{kPairs} * kRows * 4);
    for (int luma = 0; luma < 128; ++luma) {
        for (int cb = 0; cb < kRows; ++cb)
            for (int cr = 0; cr < kPairs; ++cr) {
                std::uint8_t* pair = bytes->data() + (std::size_t(cb) * kPairs + cr) * 4;
                pair[0] = static_cast<std::uint8_t>(luma);
                pair[1] = static_cast<std::uint8_t>(cb);
                pair[2] = static_cast<std::uint8_t>(luma + 128);
                pair[3] = static_cast<std::uint8_t>(cr);
            }
        const frame::CapturedImage image{frame::PixelFormat::Yuyv, 2 * kPairs, kRows, bytes};
        ASSERT_TRUE(table.use(image));
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                ASSERT_EQ(table.rgba(x, y), packedPixelRgb(image, x, y)) << "pixel " << x << ", " << y;
    }
}

TEST(CameraColourTable, FilledRgbaGivesNothingUntilAColourIsInTheTableThenWhatRgbaGives) {
    std::mt19937 rng(7);
    CameraColourTable table;
    for (const auto format : {frame::PixelFormat::Nv12, frame::PixelFormat::Yuyv}) {
        const frame::CapturedImage image = randomImage(format, 33, 21, rng);
        ASSERT_TRUE(table.use(image));
        std::size_t before = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                before += table.filledRgba(x, y).has_value();
        EXPECT_LT(before, static_cast<std::size_t>(image.width * image.height) / 10)
            << frame::toString(format) << ": random chroma is rarely met twice";
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const std::uint32_t expected = table.rgba(x, y);
                ASSERT_EQ(table.filledRgba(x, y), expected)
                    << frame::toString(format) << " " << x << ", " << y;
            }
    }
    const frame::CapturedImage rgb = randomImage(frame::PixelFormat::Rgb24, 5, 4, rng);
    ASSERT_TRUE(table.use(rgb));
    EXPECT_EQ(table.filledRgba(3, 2), packedPixelRgb(rgb, 3, 2)) << "RGB needs no table";
}

TEST(CameraColourTable, RefusesEmptyAndTruncatedImages) {
    CameraColourTable table;
    EXPECT_FALSE(table.use({}));
    EXPECT_FALSE(
        table.use({frame::PixelFormat::Nv12, 4, 4, std::make_shared<const std::vector<std::uint8_t>>(10)}));
}

TEST(PointAccumulator, ColoursAreThoseOfTheMatchingCameraPixels) {
    std::mt19937 rng(5);
    frame::Frame f = wallFrame(8, 6, 1.0f, {});
    f.capturedImage = randomImage(frame::PixelFormat::Nv12, 20, 15, rng);
    PointAccumulator acc(100, 0.001f);
    ASSERT_EQ(acc.add(f, frame::Confidence::Low, 0.0f), 48u);
    for (int v = 0; v < 6; ++v) {
        for (int u = 0; u < 8; ++u) {
            const auto [ix, iy] = cameraPixelOf(u, v, 8, 6, f.capturedImage);
            EXPECT_EQ(acc.slots()[static_cast<std::size_t>(v * 8 + u)].rgba,
                      packedPixelRgb(f.capturedImage, ix, iy));
        }
    }
}

} // namespace
} // namespace dc::processing
