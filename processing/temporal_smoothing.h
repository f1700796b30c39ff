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
    // Advances the history by one frame and returns the smoothed map.
    frame::DepthData smooth(const frame::DepthData& depth, const SmoothingParams& params);
    // Takes the last step again from the history before it: the same frame with other parameters, which
    // must not count as one more frame.
    frame::DepthData redo(const frame::DepthData& depth, const SmoothingParams& params);
    void reset();

private:
    struct History {
        frame::Plane<float> value;             // smoothed depth, 0 = none
        frame::Plane<std::uint8_t> confidence; // of the last measurement that fed the pixel
        frame::Plane<std::uint16_t> missed;    // frames since the pixel was last measured
    };
    static History step(const History& from, const frame::DepthData& depth, const SmoothingParams& params);
    frame::DepthData output(const frame::DepthData& depth) const;

    History before_; // before the last frame, for redo()
    History after_;  // after it
};

} // namespace dc::processing
