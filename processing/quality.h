#pragma once

#include "frame/frame.h"
#include "processing/settings.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dc::processing {

// Error of a depth map against ground truth of the same size.
struct DepthError {
    double mad = 0.0;  // mean absolute difference
    double rmse = 0.0; // root mean square error
    std::size_t count = 0;
};

// Over the pixels where `mask` is nonzero (all pixels without a mask). An estimate that is not a finite
// depth there counts as 0, so a method cannot improve its score by leaving pixels out.
DepthError depthError(const frame::Plane<float>& estimate, const frame::Plane<float>& truth,
                      const frame::Plane<std::uint8_t>* mask = nullptr);

// Pixels of a width x height upsampling of `low` whose bilinear footprint (all up to four neighbours) was
// measured: there every method has data, so comparing methods there is not decided by how they fill holes.
frame::Plane<std::uint8_t> measuredFootprint(const frame::Plane<float>& low, int width, int height);

// Temporal noise of a static scene before and after smoothing, over the pixels measured with at least
// medium confidence in every frame (edge pixels with mixed returns are excluded: they are not noise).
struct TemporalNoise {
    double rawFlicker = 0.0;      // RMS of frame-to-frame differences, meters
    double smoothedFlicker = 0.0; // the same after smoothing (after the warm-up frames)
    double rawSpread = 0.0;       // RMS over pixels of each pixel's standard deviation over time
    double smoothedSpread = 0.0;
    std::size_t pixels = 0;
};
TemporalNoise measureTemporalNoise(const std::vector<frame::DepthData>& frames, const SmoothingParams& params,
                                   int warmupFrames);

// Frames by which the smoothed depth lags a depth step of stepMeters moving one pixel per frame across a
// noise-free background: how many frames after the input a pixel's smoothed value passes the middle of
// the step (the worst pixel).
int measureStepLag(float stepMeters, const SmoothingParams& params);

} // namespace dc::processing
