#pragma once

#include "frame/frame.h"

#include <cstdint>
#include <deque>
#include <optional>

namespace dc::devices {

// A depth map as it came off its node, before it is paired with a camera image.
struct StampedDepth {
    std::uint64_t sequence = 0;
    std::int64_t timestampNs = 0; // 0 = unknown: pair by sequence instead
    frame::Plane<float> depthMeters;
};

struct StampedImage {
    std::uint64_t sequence = 0;
    std::int64_t timestampNs = 0;
    frame::CapturedImage image;
};

struct PairedCapture {
    StampedDepth depth;
    std::optional<StampedImage> color; // absent when no camera image was close enough in time
};

// Pairs depth and color frames that arrive on separate V4L2 nodes, each with its own queue and jitter.
// A depth frame takes the color frame nearest in time if it lies within `maxSkewNs`; with equal rates and
// maxSkewNs at most half a frame period there is at most one such frame, so a pair is released as soon as
// its color is there. A depth frame whose color cannot come any more (a color newer than its skew window
// arrived, or more than kMaxPendingDepth depth frames wait) is released alone and counted. Frames without a
// timestamp (0) pair by equal sequence numbers. Depth frames come out in the order they went in.
class FramePairer {
public:
    static constexpr std::size_t kMaxPendingDepth = 2;
    static constexpr std::size_t kMaxColors = 4;

    explicit FramePairer(std::int64_t maxSkewNs) : maxSkewNs_(maxSkewNs) {}

    void pushDepth(StampedDepth depth);
    void pushColor(StampedImage color);
    // The next depth frame whose pairing is decided, if any.
    std::optional<PairedCapture> pop();
    void reset();

    std::uint64_t paired() const { return paired_; }
    std::uint64_t unpaired() const { return unpaired_; }
    std::int64_t maxSkewNs() const { return maxSkewNs_; }

private:
    const StampedImage* match(const StampedDepth& depth) const;
    bool colorCannotCome(const StampedDepth& depth) const;

    std::int64_t maxSkewNs_;
    std::deque<StampedDepth> depth_;
    std::deque<StampedImage> colors_;
    std::uint64_t paired_ = 0;
    std::uint64_t unpaired_ = 0;
};

} // namespace dc::devices
