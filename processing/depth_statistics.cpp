#include "processing/depth_statistics.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace dc::processing {

namespace {

// The bit pattern of a positive float grows with its value, so its exponent and top mantissa bits index a
// histogram with bins of equal relative width, computed without a logarithm.
constexpr int kDroppedBits = 23 - DepthHistogram::kMantissaBits;
const std::uint32_t kLowestBits = std::bit_cast<std::uint32_t>(DepthHistogram::kLowestMeters);

// Samples looked at per frame: a 2nd percentile's rank then errs by under 0.1 % of the samples.
constexpr std::size_t kTargetSamples = std::size_t{1} << 16;

} // namespace

float DepthHistogram::binLowerMeters(std::size_t bin) {
    return std::bit_cast<float>(kLowestBits + (static_cast<std::uint32_t>(bin) << kDroppedBits));
}

DepthHistogram::DepthHistogram(const frame::Plane<float>& depthMeters) : counts_(kBins, 0) {
    const auto& pixels = depthMeters.pixels;
    const std::size_t step = std::max<std::size_t>(1, pixels.size() / kTargetSamples);
    for (std::size_t i = 0; i < pixels.size(); i += step) {
        const float d = pixels[i];
        if (!(d > 0.0f) || !std::isfinite(d)) // NaN fails the comparison
            continue;
        const float clamped = std::clamp(d, kLowestMeters, kHighestMeters);
        const std::uint32_t bits = std::bit_cast<std::uint32_t>(clamped);
        const std::size_t bin = std::min<std::size_t>((bits - kLowestBits) >> kDroppedBits, kBins - 1);
        ++counts_[bin];
        ++total_;
    }
}

float DepthHistogram::quantileMeters(double q) const {
    // The sample of rank floor(q (n - 1)) in sorted order, as a sort would pick it.
    const auto rank = static_cast<std::uint64_t>(q * static_cast<double>(total_ - 1));
    std::uint64_t below = 0;
    for (std::size_t bin = 0; bin < kBins; ++bin) {
        below += counts_[bin];
        if (below > rank)
            return binLowerMeters(bin);
    }
    return kHighestMeters;
}

std::optional<DepthRangeMeters> percentileRange(const frame::Plane<float>& depthMeters) {
    const DepthHistogram histogram(depthMeters);
    if (histogram.total() == 0)
        return std::nullopt;
    const float low = histogram.quantileMeters(0.02);
    const float high = std::max(histogram.quantileMeters(0.98), low + 0.01f);
    return DepthRangeMeters{low, high};
}

DepthRangeMeters followRange(const std::optional<DepthRangeMeters>& shown, const DepthRangeMeters& frame,
                             float fraction) {
    if (!shown)
        return frame;
    return {shown->minMeters + fraction * (frame.minMeters - shown->minMeters),
            shown->maxMeters + fraction * (frame.maxMeters - shown->maxMeters)};
}

float medianDepth(const frame::Plane<float>& depthMeters) {
    const DepthHistogram histogram(depthMeters);
    return histogram.total() == 0 ? 1.0f : histogram.quantileMeters(0.5);
}

} // namespace dc::processing
