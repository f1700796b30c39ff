#include "processing/temporal_smoothing.h"

#include <algorithm>
#include <cmath>

namespace dc::processing {

namespace {

constexpr auto kHigh = static_cast<std::uint8_t>(frame::Confidence::High);

} // namespace

void TemporalSmoother::reset() {
    before_ = {};
    after_ = {};
}

TemporalSmoother::History TemporalSmoother::step(const History& from, const frame::DepthData& depth,
                                                 const SmoothingParams& params) {
    const frame::Plane<float>& in = depth.depthMeters;
    // A size change restarts every pixel: the old history describes other pixels.
    const bool continues = from.value.width == in.width && from.value.height == in.height;
    History to{continues ? from.value : frame::Plane<float>(in.width, in.height),
               continues ? from.confidence : frame::Plane<std::uint8_t>(in.width, in.height),
               continues ? from.missed : frame::Plane<std::uint16_t>(in.width, in.height)};
    const bool hasConfidence = depth.confidence.pixels.size() == in.pixels.size();
    const float alpha = std::clamp(params.alpha, 0.0f, 1.0f);
    const float jump = std::max(params.jumpMeters, 0.0f);
    const int holeFrames = std::clamp(params.holeFrames, 0, 1000);
    for (std::size_t i = 0; i < in.pixels.size(); ++i) {
        const float d = in.pixels[i];
        float& s = to.value.pixels[i];
        if (std::isfinite(d) && d > 0.0f) {
            // A first sample, or a jump too large to be noise, restarts the pixel at the measurement.
            s = s > 0.0f && std::abs(d - s) <= jump ? s + alpha * (d - s) : d;
            to.missed.pixels[i] = 0;
            to.confidence.pixels[i] = hasConfidence ? depth.confidence.pixels[i] : kHigh;
        } else if (s > 0.0f && to.missed.pixels[i] < holeFrames) {
            ++to.missed.pixels[i];
        } else {
            s = 0.0f;
            to.confidence.pixels[i] = 0;
        }
    }
    return to;
}

frame::DepthData TemporalSmoother::output(const frame::DepthData& depth) const {
    frame::DepthData out{after_.value, {}, depth.confidenceEstimated};
    if (depth.confidence.pixels.size() == depth.depthMeters.pixels.size())
        out.confidence = after_.confidence;
    return out;
}

frame::DepthData TemporalSmoother::smooth(const frame::DepthData& depth, const SmoothingParams& params) {
    before_ = std::move(after_);
    after_ = step(before_, depth, params);
    return output(depth);
}

frame::DepthData TemporalSmoother::redo(const frame::DepthData& depth, const SmoothingParams& params) {
    after_ = step(before_, depth, params);
    return output(depth);
}

} // namespace dc::processing
