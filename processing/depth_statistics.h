#pragma once

#include "frame/frame.h"
#include "processing/shown_frame.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace dc::processing {

// The valid depths of a frame (finite, above zero), counted in one pass into bins of equal relative width
// (1/1024 of the depth: 2.4 mm at 2.5 m) from 1 mm to 16 km; depths beyond either end count in the end bin.
// A large frame is subsampled to about 65,000 samples. A quantile is the lower edge of the bin that holds
// the sample a sort would pick, so it is within one bin of the sorted answer.
class DepthHistogram {
public:
    static constexpr int kMantissaBits = 10;
    static constexpr float kLowestMeters = 1.0f / 1024.0f;
    static constexpr float kHighestMeters = 16384.0f;
    static constexpr std::size_t kBins = std::size_t{24} << kMantissaBits; // 24 powers of two, 1024 each

    explicit DepthHistogram(const frame::Plane<float>& depthMeters);
    std::uint64_t total() const { return total_; }
    // The q-quantile (0 .. 1) of the samples counted; needs total() > 0.
    float quantileMeters(double q) const;
    static float binLowerMeters(std::size_t bin);

private:
    std::vector<std::uint32_t> counts_;
    std::uint64_t total_ = 0;
};

// The automatic colormap range: the 2nd to 98th percentile of the valid depth, so a few outliers do not
// flatten the ramp; at least a centimetre wide. None without a valid sample.
std::optional<DepthRangeMeters> percentileRange(const frame::Plane<float>& depthMeters);

// The automatic range over time: each new frame moves the range shown `fraction` of the way to that frame's
// percentiles, so the colours follow the scene without pumping with every frame's outliers. None before:
// the frame's range as it is.
DepthRangeMeters followRange(const std::optional<DepthRangeMeters>& shown, const DepthRangeMeters& frame,
                             float fraction);

// The median valid depth (1 m without one): the orbit's pivot, so the swing turns the cloud about the
// middle of the scene.
float medianDepth(const frame::Plane<float>& depthMeters);

} // namespace dc::processing
