#include "processing/confidence_filter.h"

namespace dc::processing {

namespace {
constexpr auto kHigh = static_cast<std::uint8_t>(frame::Confidence::High);

std::uint8_t confidenceAt(const frame::DepthData& depth, std::size_t i) {
    return depth.confidence.empty() ? kHigh : depth.confidence.pixels[i];
}
} // namespace

frame::Plane<float> filterByConfidence(const frame::DepthData& depth, frame::Confidence minLevel) {
    frame::Plane<float> out(depth.depthMeters.width, depth.depthMeters.height);
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        const float d = depth.depthMeters.pixels[i];
        out.pixels[i] = keepSample(d, confidenceAt(depth, i), minLevel, 0.0f) ? d : 0.0f;
    }
    return out;
}

std::size_t countDrawablePoints(const frame::DepthData& depth, frame::Confidence minLevel, float nearMeters) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < depth.depthMeters.pixels.size(); ++i)
        count += keepSample(depth.depthMeters.pixels[i], confidenceAt(depth, i), minLevel, nearMeters);
    return count;
}

} // namespace dc::processing
