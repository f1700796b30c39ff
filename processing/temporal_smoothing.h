#pragma once

#include "frame/frame.h"
#include "processing/settings.h"

#include <cstdint>

namespace dc::processing {

// ARKit's smoothedSceneDepth for sources that lack it: per pixel, an exponential average in meters that
// keeps edges (a change beyond jumpMeters restarts the history instead of blending across it) and bridges
// short dropouts (a pixel that loses its measurement keeps its value for holeFrames frames).
// Invalid input (0, NaN, inf, negative) is a dropout, never averaged in. A size change restarts it.
class TemporalSmoother {
public:
    frame::DepthData smooth(const frame::DepthData& depth, const SmoothingParams& params);
    void reset();

private:
    frame::Plane<float> value_;             // smoothed depth, 0 = none
    frame::Plane<std::uint8_t> confidence_; // of the last measurement that fed the pixel
    frame::Plane<std::uint16_t> missed_;    // frames since the pixel was last measured
};

} // namespace dc::processing
