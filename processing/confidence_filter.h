#pragma once

#include "frame/frame.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace dc::processing {

// Whether a depth sample becomes a point: a finite, positive depth at or beyond the near limit, with a
// confidence at or above the selected level. The cloud's vertex shader applies the same rule.
inline bool keepSample(float depthMeters, std::uint8_t confidence, frame::Confidence minLevel,
                       float nearMeters) {
    // Bitwise: no branch, so that loops over samples vectorise.
    return std::isfinite(depthMeters) & (depthMeters > 0.0f) & (depthMeters >= nearMeters) &
           (confidence >= static_cast<std::uint8_t>(minLevel));
}

// Depth with every sample below `minLevel` (or invalid: NaN, inf, negative) set to 0 = no measurement.
// Without a confidence map every valid sample is kept.
frame::Plane<float> filterByConfidence(const frame::DepthData& depth, frame::Confidence minLevel);

// How many points the cloud draws for this depth map, level and near limit.
std::size_t countDrawablePoints(const frame::DepthData& depth, frame::Confidence minLevel, float nearMeters);

} // namespace dc::processing
