#pragma once

#include "devices/frame.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace dc::processing {

// A point in world coordinates with its colour packed as R, G, B, A bytes (little-endian RGBA8, as the
// GPU reads it).
struct WorldPoint {
    float x = 0, y = 0, z = 0;
    std::uint32_t rgba = 0;
};

// The WWDC20 "accumulate" mode: every posed frame adds its points, in world coordinates, to a bounded
// budget. The oldest points leave first when the budget is full, and a point whose voxel already holds
// one is not added again, so a camera dwelling on a surface does not fill the budget with copies of it.
//
// Storage is a ring of `budget` slots plus a flat open-addressing hash from voxel to slot: adding a frame
// costs one unprojection, one transform and one probe per sample, and colour conversion only for the
// samples that are new.
class PointAccumulator {
public:
    static constexpr std::size_t kDefaultBudget = 1'000'000;
    static constexpr float kDefaultVoxelMeters = 0.005f;

    explicit PointAccumulator(std::size_t budget = kDefaultBudget, float voxelMeters = kDefaultVoxelMeters);

    // Changes the budget or voxel size; either change clears what was accumulated.
    void configure(std::size_t budget, float voxelMeters);
    // Adds the frame's kept samples (confidence and near limit as the cloud draws them). A frame without
    // a pose or depth adds nothing. Returns the number of points added.
    std::size_t add(const devices::Frame& frame, devices::Confidence minLevel, float nearMeters);
    void clear();

    std::size_t size() const { return count_; }
    std::size_t budget() const { return points_.size(); }
    float voxelMeters() const { return voxelMeters_; }
    // All slots; the first size() of them hold points until the ring wraps, then all do.
    const std::vector<WorldPoint>& slots() const { return points_; }
    // Slot ranges [begin, end) written since the last takeDirty() (for uploading only what changed).
    std::vector<std::pair<std::size_t, std::size_t>> takeDirty();
    // Counts clears and reconfigurations, so a consumer can tell its copy is stale as a whole.
    std::uint64_t generation() const { return generation_; }

private:
    static constexpr std::uint64_t kEmpty = ~0ull;

    std::uint64_t voxelKey(float x, float y, float z) const;
    std::size_t bucketOf(std::uint64_t key) const;
    // Index of the bucket holding `key`, or of the empty bucket where it would go.
    std::size_t find(std::uint64_t key) const;
    void erase(std::uint64_t key);
    void store(const WorldPoint& point, std::uint64_t key);

    float voxelMeters_;
    std::vector<WorldPoint> points_;
    std::vector<std::uint64_t> pointKeys_; // voxel of each slot, to free it when the slot is reused
    std::vector<std::uint64_t> keys_;      // hash buckets: voxel key or kEmpty
    std::vector<std::uint32_t> slotOf_;    // hash buckets: the slot holding that voxel's point
    std::size_t next_ = 0;
    std::size_t count_ = 0;
    std::size_t dirtyBegin_ = 0;
    std::size_t dirtyCount_ = 0;
    std::uint64_t generation_ = 0;
};

} // namespace dc::processing
