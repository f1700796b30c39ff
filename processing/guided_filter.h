#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"

#include <cstdint>

namespace dc::processing {

// The guided filter (He, Sun, Tang, "Guided Image Filtering", 2013) as a depth upsampler, with three
// changes that matter for depth:
// - masked: a sample without measurement (0, NaN, inf, negative) has weight 0, so it is never averaged in
//   as a depth of zero, and every window statistic is normalised by the weight it actually has;
// - fit-weighted (optional): each window's linear model a * guide + b is averaged into the output with a
//   weight 1 / (1 + cost / fitNoise^2)^2, where cost is the window's regression cost (squared residual plus
//   epsilon a^2): windows that straddle a depth edge hardly count, and windows on one surface average noise
//   over the whole radius;
// - numerically safe for any depth range: depths are centred on their mean, window sums accumulate in
//   double, variances are clamped at 0, and epsilon is in squared guide intensity (guide in [0, 1]), so the
//   result scales and shifts exactly with the depth's units and offset (up to the fitNoise weighting).
struct GuidedFilterParams {
    int radius = 8;          // window radius in output pixels (clipped at the image border)
    float epsilon = 1e-3f;   // regulariser, squared guide intensity
    int subsample = 1;       // 1: full guided filter; s > 1: fast guided filter, coefficients at 1/s
    bool fitWeighted = true; // false: He's plain average of the window coefficients
    float fitNoise = 0.002f; // residual spread that counts as a good fit, in the depth's units
};

// The filter on one grid. `guide` in [0, 1], `depth` and `weight` of the same size; weight 0 marks a
// sample without measurement, as does a depth that is not finite and positive. The output has depth only
// where the input sample has weight >= 0.5 (no hole filling); elsewhere 0.
frame::Plane<float> maskedGuidedFilter(const frame::Plane<float>& guide, const frame::Plane<float>& depth,
                                       const frame::Plane<float>& weight, const GuidedFilterParams& params);

// Upsamples depth maps to an output size, guided by a camera image: depth and confidence are first scaled
// bilinearly (masked: holes stay holes and do not pull their neighbours towards 0), then filtered with the
// guide. Confidence follows the bilinear map, rounded; a pixel without depth in the output has depth 0.
// Keeps its buffers between frames; setGuide() once per frame, then upsample() each depth map of it.
class GuidedUpsampler {
public:
    void setGuide(GrayView guide, int outputWidth, int outputHeight, const GuidedFilterParams& params);
    frame::DepthData upsample(const frame::DepthData& depth) const;

private:
    GuidedFilterParams params_;
    frame::Plane<std::uint8_t> guideOutput_; // 8-bit guide at the output size
    frame::Plane<float> guideGrid_; // guide in [0, 1] on the coefficient grid (the output size for s = 1)
};

// One-shot form of GuidedUpsampler.
frame::DepthData guidedUpsample(const frame::DepthData& depth, GrayView guide, int outputWidth,
                                int outputHeight, const GuidedFilterParams& params);

} // namespace dc::processing
