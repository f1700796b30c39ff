#include "processing/point_accumulator.h"

#include "devices/color.h"
#include "processing/confidence_filter.h"
#include "processing/point_cloud.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace dc::processing {

namespace {

std::uint32_t packRgba(const devices::Rgb& c) {
    return static_cast<std::uint32_t>(devices::toByte(c.r)) |
           static_cast<std::uint32_t>(devices::toByte(c.g)) << 8 |
           static_cast<std::uint32_t>(devices::toByte(c.b)) << 16 | 0xff000000u;
}

// The camera-to-world transform in float, row-major 3x4: enough precision for points within a few
// kilometres of the origin at a millimetre voxel.
std::array<float, 12> rowMajor(const devices::Pose& pose) {
    const auto& m = pose.cameraToWorld; // column-major 4x4
    std::array<float, 12> r{};
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
            r[static_cast<std::size_t>(row * 4 + col)] =
                static_cast<float>(m[static_cast<std::size_t>(col * 4 + row)]);
    return r;
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
    pointKeys_.assign(budget, kEmpty);
    keys_.assign(std::bit_ceil(budget * 2), kEmpty);
    slotOf_.assign(keys_.size(), 0);
    next_ = count_ = dirtyBegin_ = dirtyCount_ = 0;
    ++generation_;
}

void PointAccumulator::clear() {
    std::fill(pointKeys_.begin(), pointKeys_.end(), kEmpty);
    std::fill(keys_.begin(), keys_.end(), kEmpty);
    next_ = count_ = dirtyBegin_ = dirtyCount_ = 0;
    ++generation_;
}

// 21 bits per axis, offset so that +-5 km at 5 mm stays in range; points beyond wrap harmlessly.
std::uint64_t PointAccumulator::voxelKey(float x, float y, float z) const {
    constexpr std::int64_t kOffset = 1 << 20;
    const auto cell = [&](float v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxelMeters_)) + kOffset) &
               0x1fffffu;
    };
    return cell(x) | cell(y) << 21 | cell(z) << 42;
}

std::size_t PointAccumulator::bucketOf(std::uint64_t key) const {
    // Fibonacci hashing spreads neighbouring voxels over the table.
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ull) >> (64 - std::countr_zero(keys_.size())));
}

std::size_t PointAccumulator::find(std::uint64_t key) const {
    const std::size_t mask = keys_.size() - 1;
    std::size_t i = bucketOf(key);
    while (keys_[i] != kEmpty && keys_[i] != key)
        i = (i + 1) & mask;
    return i;
}

// Linear-probing deletion by backward shift: later entries of the same probe run move up, so lookups
// never stop early at a hole.
void PointAccumulator::erase(std::uint64_t key) {
    const std::size_t mask = keys_.size() - 1;
    std::size_t hole = find(key);
    if (keys_[hole] == kEmpty)
        return;
    std::size_t i = hole;
    while (true) {
        i = (i + 1) & mask;
        if (keys_[i] == kEmpty)
            break;
        const std::size_t home = bucketOf(keys_[i]);
        // Move the entry into the hole unless its home lies cyclically in (hole, i].
        const bool homeBetween = hole <= i ? (home > hole && home <= i) : (home > hole || home <= i);
        if (!homeBetween) {
            keys_[hole] = keys_[i];
            slotOf_[hole] = slotOf_[i];
            hole = i;
        }
    }
    keys_[hole] = kEmpty;
}

void PointAccumulator::store(const WorldPoint& point, std::uint64_t key) {
    if (pointKeys_[next_] != kEmpty)
        erase(pointKeys_[next_]); // the oldest point leaves
    const std::size_t bucket = find(key);
    keys_[bucket] = key;
    slotOf_[bucket] = static_cast<std::uint32_t>(next_);
    pointKeys_[next_] = key;
    points_[next_] = point;
    if (dirtyCount_ == 0)
        dirtyBegin_ = next_;
    dirtyCount_ = std::min(dirtyCount_ + 1, points_.size());
    next_ = (next_ + 1) % points_.size();
    count_ = std::min(count_ + 1, points_.size());
}

std::size_t PointAccumulator::add(const devices::Frame& frame, devices::Confidence minLevel,
                                  float nearMeters) {
    if (!frame.pose || !frame.sceneDepth || !frame.cameraIntrinsics.valid())
        return 0;
    const devices::DepthData& depth = *frame.sceneDepth;
    const devices::Intrinsics k = frame.depthIntrinsics();
    const std::array<float, 12> m = rowMajor(*frame.pose);
    const int w = depth.depthMeters.width, h = depth.depthMeters.height;
    std::size_t added = 0;
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const float z = depth.depthMeters.at(u, v);
            const std::uint8_t c = depth.confidence.empty() ? 2 : depth.confidence.at(u, v);
            if (!keepSample(z, c, minLevel, nearMeters))
                continue;
            const auto [x, y, zz] = unproject(u, v, z, k);
            const WorldPoint p{m[0] * x + m[1] * y + m[2] * zz + m[3], m[4] * x + m[5] * y + m[6] * zz + m[7],
                               m[8] * x + m[9] * y + m[10] * zz + m[11], 0};
            const std::uint64_t key = voxelKey(p.x, p.y, p.z);
            if (keys_[find(key)] == key)
                continue;
            const auto [ix, iy] = cameraPixelOf(u, v, w, h, frame.capturedImage);
            store({p.x, p.y, p.z, packRgba(devices::pixelRgb(frame.capturedImage, ix, iy))}, key);
            ++added;
        }
    }
    return added;
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
