#include "processing/depth_statistics.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dc::processing {

namespace {

// Every `step`-th valid sample: plenty for a percentile, and a fraction of the cost.
std::vector<float> validSamples(const frame::Plane<float>& depthMeters, std::size_t step) {
    std::vector<float> valid;
    const auto& pixels = depthMeters.pixels;
    valid.reserve(pixels.size() / step + 1);
    for (std::size_t i = 0; i < pixels.size(); i += step)
        if (std::isfinite(pixels[i]) && pixels[i] > 0.0f)
            valid.push_back(pixels[i]);
    return valid;
}

float quantile(std::vector<float>& valid, double q) {
    const auto it = valid.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(valid.size() - 1));
    std::nth_element(valid.begin(), it, valid.end());
    return *it;
}

} // namespace

std::optional<DepthRangeMeters> percentileRange(const frame::Plane<float>& depthMeters) {
    std::vector<float> valid = validSamples(depthMeters, 2);
    if (valid.empty())
        return std::nullopt;
    const float low = quantile(valid, 0.02);
    const float high = std::max(quantile(valid, 0.98), low + 0.01f);
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
    std::vector<float> valid = validSamples(depthMeters, 4);
    return valid.empty() ? 1.0f : quantile(valid, 0.5);
}

} // namespace dc::processing
