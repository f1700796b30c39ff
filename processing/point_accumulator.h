#pragma once

#include "frame/frame.h"
#include "processing/point_cloud.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
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
// Storage is a ring of `budget` slots plus a sparse bitmap of the occupied voxels: a voxel holds at most
// one point, so eviction only clears the evicted point's bit. The bitmap is a hash table of blocks of
// 4 x 4 x 4 voxels, each entry a block's coordinates and its 64 bits; a block leaves the table when its
// last point does. At a fine voxel nearly every sample lands in a block far from the previous one in
// memory, so the cost is cache misses: adding first computes the whole frame's voxels (on two threads),
// then loads the entries a chunk of samples and its evictions will need in independent passes, so that
// the misses overlap, before the sequential de-dup and eviction. Colours are the samples' own (the
// shown cloud's), packed only for the samples that are new.
class PointAccumulator {
public:
    static constexpr std::size_t kDefaultBudget = 1'000'000;
    static constexpr float kDefaultVoxelMeters = 0.005f;

    explicit PointAccumulator(std::size_t budget = kDefaultBudget, float voxelMeters = kDefaultVoxelMeters);

    // Changes the budget or voxel size; either change clears what was accumulated.
    void configure(std::size_t budget, float voxelMeters);
    // Adds the kept samples (confidence and near limit as the cloud draws them), moved into the world by
    // `pose`. Unusable samples add nothing. Returns the number of points added.
    std::size_t add(const CloudSamples& samples, const frame::Pose& pose, frame::Confidence minLevel,
                    float nearMeters);
    // The raw frame's samples (buildPointCloud's), through its pose; nothing without one.
    std::size_t add(const frame::Frame& frame, frame::Confidence minLevel, float nearMeters);
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

    // A block of 4 x 4 x 4 voxels: its coordinates and its occupancy, bit x % 4 + 4 * (y % 4) + 16 * (z % 4).
    struct TableEntry {
        std::uint64_t key = kEmpty;
        std::uint64_t bits = 0;
    };
    // A sample of the frame being added; if kept, in world coordinates with its voxel.
    struct Candidate {
        WorldPoint point;
        std::uint64_t blockKey = 0;
        std::uint64_t hash = 0; // of the block key, for table_ at any size
        std::uint32_t bit = 0;  // voxel within the block
        int u = 0, v = 0;
        bool kept = false;
    };

    std::size_t homeOf(std::uint64_t blockKey) const;
    std::size_t homeOfHash(std::uint64_t hash) const { return static_cast<std::size_t>(hash >> tableShift_); }
    // Index of the table entry holding `blockKey`, or of the empty entry where it would go.
    std::size_t findEntry(std::uint64_t blockKey, std::size_t home) const;
    std::size_t addBlock(std::size_t at, std::uint64_t blockKey);
    void eraseEntry(std::size_t at);
    void resetBlocks();
    bool evictOldest();
    void gatherRow(const CloudSamples& samples, const std::array<float, 12>& m, int v,
                   frame::Confidence minLevel, float nearMeters, Candidate* out) const;
    std::uint64_t touchFor(std::size_t begin, std::size_t end) const;
    std::size_t insertCandidates(const CloudSamples& samples);
    void store(const WorldPoint& point, std::uint64_t voxel);

    float voxelMeters_;
    std::vector<WorldPoint> points_;
    std::vector<std::uint64_t> slotVoxels_; // block key << 6 | bit of each slot's voxel, or kEmpty
    std::vector<TableEntry> table_;         // open addressing, linear probing, at most half full
    int tableShift_ = 0;
    std::size_t tableCount_ = 0;
    std::vector<Candidate> candidates_; // scratch, kept to reuse its allocation
    std::uint64_t touched_ = 0; // what touchFor loaded, kept so that its loads are not optimised away
    std::size_t next_ = 0;
    std::size_t count_ = 0;
    std::size_t dirtyBegin_ = 0;
    std::size_t dirtyCount_ = 0;
    std::uint64_t generation_ = 0;
};

} // namespace dc::processing
