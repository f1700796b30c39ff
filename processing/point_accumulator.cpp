#include "processing/point_accumulator.h"

#include "frame/color.h"
#include "processing/confidence_filter.h"
#include "processing/parallel.h"
#include "processing/point_cloud.h"
#include "processing/point_colours.h"
#include "processing/registration.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace dc::processing {

namespace {

// Candidates whose memory is requested together: enough misses in flight to hide memory latency, few
// enough that the lines stay in the first-level cache until they are used.
constexpr std::size_t kChunk = 256;
// Depth rows per thread below which gathering runs on one thread.
constexpr int kMinRowsPerThread = 32;
constexpr std::size_t kInitialTable = 4096;
constexpr std::uint64_t kCellMask = 0x1fffff;

// The camera-to-world transform in float, row-major 3x4: enough precision for points within a few
// kilometres of the origin at a millimetre voxel.
std::array<float, 12> rowMajor(const frame::Pose& pose) {
    const auto& m = pose.cameraToWorld; // column-major 4x4
    std::array<float, 12> r{};
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
            r[static_cast<std::size_t>(row * 4 + col)] =
                static_cast<float>(m[static_cast<std::size_t>(col * 4 + row)]);
    return r;
}

// MurmurHash3's finaliser. The blocks of a surface form a lattice of keys, which a plain multiplicative
// hash maps onto long probe runs.
std::uint64_t mix(std::uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    return k ^ (k >> 33);
}

// A voxel's cell along one axis: 21 bits, offset so that +-1 km at 1 mm stays in range; points beyond
// wrap harmlessly.
std::uint64_t cellOf(float v, float voxelMeters) {
    constexpr std::int64_t kOffset = 1 << 20;
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxelMeters)) + kOffset) &
           kCellMask;
}

} // namespace

PointAccumulator::PointAccumulator(std::size_t budget, float voxelMeters) : voxelMeters_(voxelMeters) {
    configure(budget, voxelMeters);
}

void PointAccumulator::configure(std::size_t budget, float voxelMeters) {
    budget = std::max<std::size_t>(budget, 1);
    if (!(voxelMeters > 0.0f) || !std::isfinite(voxelMeters))
        voxelMeters = kDefaultVoxelMeters;
    if (budget == points_.size() && voxelMeters == voxelMeters_)
        return;
    voxelMeters_ = voxelMeters;
    points_.assign(budget, {});
    slotVoxels_.assign(budget, kEmpty);
    resetBlocks();
    next_ = count_ = dirtyBegin_ = dirtyCount_ = 0;
    ++generation_;
}

void PointAccumulator::clear() {
    std::fill(slotVoxels_.begin(), slotVoxels_.end(), kEmpty);
    resetBlocks();
    next_ = count_ = dirtyBegin_ = dirtyCount_ = 0;
    ++generation_;
}

void PointAccumulator::resetBlocks() {
    table_.assign(kInitialTable, TableEntry{});
    tableShift_ = 64 - std::countr_zero(kInitialTable);
    tableCount_ = 0;
}

std::size_t PointAccumulator::homeOf(std::uint64_t blockKey) const {
    return homeOfHash(mix(blockKey));
}

std::size_t PointAccumulator::findEntry(std::uint64_t blockKey, std::size_t home) const {
    const std::size_t mask = table_.size() - 1;
    std::size_t i = home;
    while (table_[i].key != kEmpty && table_[i].key != blockKey)
        i = (i + 1) & mask;
    return i;
}

// Enters an empty block for `blockKey` at the empty table entry `at`; returns where it is, which moves
// if the table grew.
std::size_t PointAccumulator::addBlock(std::size_t at, std::uint64_t blockKey) {
    table_[at] = {blockKey, 0};
    if (++tableCount_ * 2 <= table_.size())
        return at;
    // Keep the table at most half full, so that probe runs stay short.
    decltype(table_) old(table_.size() * 2);
    old.swap(table_);
    tableShift_ -= 1;
    for (const TableEntry& e : old)
        if (e.key != kEmpty)
            table_[findEntry(e.key, homeOf(e.key))] = e;
    return findEntry(blockKey, homeOf(blockKey));
}

// Linear-probing deletion by backward shift: later entries of the same probe run move up, so lookups
// never stop early at a hole.
void PointAccumulator::eraseEntry(std::size_t hole) {
    const std::size_t mask = table_.size() - 1;
    std::size_t i = hole;
    while (true) {
        i = (i + 1) & mask;
        if (table_[i].key == kEmpty)
            break;
        const std::size_t home = homeOf(table_[i].key);
        // Move the entry into the hole unless its home lies cyclically in (hole, i].
        const bool homeBetween = hole <= i ? (home > hole && home <= i) : (home > hole || home <= i);
        if (!homeBetween) {
            table_[hole] = table_[i];
            hole = i;
        }
    }
    table_[hole] = TableEntry{};
    --tableCount_;
}

// Frees the oldest slot's voxel; true if that emptied its block, which then left the table.
bool PointAccumulator::evictOldest() {
    const std::uint64_t voxel = slotVoxels_[next_];
    if (voxel == kEmpty)
        return false;
    const std::size_t at = findEntry(voxel >> 6, homeOf(voxel >> 6));
    table_[at].bits &= ~(std::uint64_t{1} << (voxel & 63));
    if (table_[at].bits != 0)
        return false;
    eraseEntry(at);
    return true;
}

// Row v's samples as candidates at out[0, width): kept ones in world coordinates with their voxel, the
// others marked unkept. Touches nothing else, so rows may run on several threads.
void PointAccumulator::gatherRow(const CloudSamples& samples, const std::array<float, 12>& m, int v,
                                 frame::Confidence minLevel, float nearMeters, Candidate* out) const {
    const frame::DepthData& depth = *samples.depth;
    const frame::Intrinsics& k = samples.intrinsics;
    for (int u = 0; u < depth.depthMeters.width; ++u) {
        Candidate& c = out[u];
        const float z = depth.depthMeters.at(u, v);
        const std::uint8_t conf = depth.confidence.empty() ? 2 : depth.confidence.at(u, v);
        c.kept = keepSample(z, conf, minLevel, nearMeters);
        if (!c.kept)
            continue;
        const auto [x, y, zz] = unproject(u, v, z, k);
        c.point = {m[0] * x + m[1] * y + m[2] * zz + m[3], m[4] * x + m[5] * y + m[6] * zz + m[7],
                   m[8] * x + m[9] * y + m[10] * zz + m[11], 0};
        const std::uint64_t cx = cellOf(c.point.x, voxelMeters_), cy = cellOf(c.point.y, voxelMeters_),
                            cz = cellOf(c.point.z, voxelMeters_);
        c.blockKey = cx >> 2 | (cy >> 2) << 19 | (cz >> 2) << 38;
        c.hash = mix(c.blockKey);
        c.bit = static_cast<std::uint32_t>((cx & 3) | (cy & 3) << 2 | (cz & 3) << 4);
        c.u = u;
        c.v = v;
    }
}

// Loads what candidates [begin, end) will touch, in passes whose loads do not wait on one another, so
// that their cache misses overlap: their table entries, and those of the voxels that the evictions they
// may cause will clear (slots leave in ring order). Plain loads rather than prefetch hints, which the
// processor drops when many misses are already in flight.
std::uint64_t PointAccumulator::touchFor(std::size_t begin, std::size_t end) const {
    std::uint64_t sink = 0;
    for (std::size_t i = begin; i < end; ++i)
        if (candidates_[i].kept)
            sink ^= table_[homeOfHash(candidates_[i].hash)].key;
    std::size_t slot = next_;
    for (std::size_t i = begin; i < end; ++i) {
        if (slotVoxels_[slot] != kEmpty)
            sink ^= table_[homeOf(slotVoxels_[slot] >> 6)].key;
        slot = slot + 1 == points_.size() ? 0 : slot + 1;
    }
    return sink;
}

std::size_t PointAccumulator::insertCandidates(const CloudSamples& samples) {
    const int w = samples.depth->depthMeters.width;
    const std::uint8_t gray[3] = {128, 128, 128}; // pixelRgb's colour without an image
    std::size_t added = 0;
    for (std::size_t i = 0; i < candidates_.size(); ++i) {
        if (i % kChunk == 0)
            touched_ ^= touchFor(i, std::min(candidates_.size(), i + kChunk));
        const Candidate& c = candidates_[i];
        if (!c.kept)
            continue;
        std::size_t at = findEntry(c.blockKey, homeOfHash(c.hash));
        const std::uint64_t bit = std::uint64_t{1} << c.bit;
        if (table_[at].key == c.blockKey && (table_[at].bits & bit))
            continue; // the voxel already holds a point
        if (evictOldest())
            at = findEntry(c.blockKey, homeOfHash(c.hash)); // the table changed under `at`
        if (table_[at].key != c.blockKey)
            at = addBlock(at, c.blockKey);
        table_[at].bits |= bit;
        const std::uint8_t* rgb =
            samples.colours ? &samples.colours->pixels[(static_cast<std::size_t>(c.v) * w + c.u) * 3] : gray;
        store({c.point.x, c.point.y, c.point.z, packRgba(rgb)}, c.blockKey << 6 | c.bit);
        ++added;
    }
    return added;
}

void PointAccumulator::store(const WorldPoint& point, std::uint64_t voxel) {
    slotVoxels_[next_] = voxel;
    points_[next_] = point;
    if (dirtyCount_ == 0)
        dirtyBegin_ = next_;
    dirtyCount_ = std::min(dirtyCount_ + 1, points_.size());
    next_ = next_ + 1 == points_.size() ? 0 : next_ + 1;
    count_ = std::min(count_ + 1, points_.size());
}

std::size_t PointAccumulator::add(const CloudSamples& samples, const frame::Pose& pose,
                                  frame::Confidence minLevel, float nearMeters) {
    if (!samples.usable())
        return 0;
    const int w = samples.depth->depthMeters.width, h = samples.depth->depthMeters.height;
    const std::array<float, 12> m = rowMajor(pose);
    candidates_.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    parallelRanges(h, kMinRowsPerThread, [&](int begin, int end) {
        for (int v = begin; v < end; ++v)
            gatherRow(samples, m, v, minLevel, nearMeters, &candidates_[static_cast<std::size_t>(v) * w]);
    });
    return insertCandidates(samples);
}

std::size_t PointAccumulator::add(const frame::Frame& frame, frame::Confidence minLevel, float nearMeters) {
    if (!frame.pose || !frame.sceneDepth)
        return 0;
    const auto& d = frame.sceneDepth->depthMeters;
    CameraColourTable table;
    const PointColours colours = framePointColours(frame, d, table);
    return add({&*frame.sceneDepth, frame.depthIntrinsics(), colours.colours.get()}, *frame.pose, minLevel,
               nearMeters);
}

std::vector<std::pair<std::size_t, std::size_t>> PointAccumulator::takeDirty() {
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    const std::size_t end = dirtyBegin_ + dirtyCount_;
    if (end <= points_.size()) {
        if (dirtyCount_ > 0)
            ranges.emplace_back(dirtyBegin_, end);
    } else {
        ranges.emplace_back(dirtyBegin_, points_.size());
        ranges.emplace_back(0, end - points_.size());
    }
    dirtyCount_ = 0;
    return ranges;
}

} // namespace dc::processing
