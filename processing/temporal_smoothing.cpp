#include "processing/temporal_smoothing.h"

#include <algorithm>
#include <cmath>

namespace dc::processing {

namespace {

constexpr auto kHigh = static_cast<std::uint8_t>(frame::Confidence::High);

} // namespace

void TemporalSmoother::reset() {
    value_ = {};
    confidence_ = {};
    missed_ = {};
}

frame::DepthData TemporalSmoother::smooth(const frame::DepthData& depth, const SmoothingParams& params) {
    const frame::Plane<float>& in = depth.depthMeters;
    if (value_.width != in.width || value_.height != in.height) {
        value_ = frame::Plane<float>(in.width, in.height);
        confidence_ = frame::Plane<std::uint8_t>(in.width, in.height);
        missed_ = frame::Plane<std::uint16_t>(in.width, in.height);
    }
    const bool hasConfidence = depth.confidence.pixels.size() == in.pixels.size();
    const float alpha = std::clamp(params.alpha, 0.0f, 1.0f);
    const float jump = std::max(params.jumpMeters, 0.0f);
    const int holeFrames = std::clamp(params.holeFrames, 0, 1000);
    for (std::size_t i = 0; i < in.pixels.size(); ++i) {
        const float d = in.pixels[i];
        float& s = value_.pixels[i];
        if (std::isfinite(d) && d > 0.0f) {
            // A first sample, or a jump too large to be noise, restarts the pixel at the measurement.
            s = s > 0.0f && std::abs(d - s) <= jump ? s + alpha * (d - s) : d;
            missed_.pixels[i] = 0;
            confidence_.pixels[i] = hasConfidence ? depth.confidence.pixels[i] : kHigh;
        } else if (s > 0.0f && missed_.pixels[i] < holeFrames) {
            ++missed_.pixels[i];
        } else {
            s = 0.0f;
            confidence_.pixels[i] = 0;
        }
    }
    frame::DepthData out{value_, {}, depth.confidenceEstimated};
    if (hasConfidence)
        out.confidence = confidence_;
    return out;
}

} // namespace dc::processing
