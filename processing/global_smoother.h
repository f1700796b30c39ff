#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"

#include <cstddef>
#include <cstdint>
#include <memory>

namespace dc::processing {

// One weighted-least-squares pass: minimises sum_p c_p (u_p - f_p)^2 + lambda sum_pq w_pq (u_p - u_q)^2 over
// 4-neighbours p, q, approximated as in the fast global smoother by alternating 1-D horizontal and vertical
// solves. The neighbour weight w_pq is the product of a colour term and a depth term (each 1 when its sigma
// is 0).
struct SmootherPass {
    // Smoothness: over a region of uniform guide, a sample's influence spreads over about sqrt(lambda)
    // pixels of the pass's grid.
    float lambda = 0.0f;
    // Horizontal + vertical sweeps, lambda falling by 4 from one to the next (FGS's schedule). 0 = no pass.
    int iterations = 0;
    // Colour term 1 / (1 + (d / colorSigma)^8), d the Euclidean distance of the two pixels' 8-bit colours:
    // flat below colorSigma, so texture does not stop smoothing, and nearly 0 beyond twice it.
    float colorSigma = 0.0f;
    // Depth term 1 / (1 + (dz / depthSigma)^2)^2, dz the difference of the previous pass's depths (depth
    // units): a step much larger than depthSigma stays sharp.
    float depthSigma = 0.0f;
};

// The dual-guided global smoother's parameters, in the depth's own units (meters for frames, disparity levels
// for the benchmark's scenes). upsamplingSmootherParams() (upsampling_stage.h) derives them from the
// user's settings and the upsampling factor.
struct GlobalSmootherParams {
    // At the sensor's resolution, where every sample is an independent measurement: denoising. First guided
    // by the colour image reduced to the sensor's size, then by that result's own depth (smoothing out what
    // colour texture left) with the colour term kept as a weak guard.
    SmootherPass sensorColor;
    SmootherPass sensorDepth;
    // The depth pass repeated, each round guided by the last one's result (iteratively reweighted least
    // squares): edges the first round blurred a little are sharper in the next one's weights.
    int sensorDepthRounds = 1;
    // At the output resolution, on the bilinear upsampling of the denoised map: edges. Guided by the colour
    // image, then by that result's depth.
    SmootherPass outputColor;
    SmootherPass outputDepth;
    int outputDepthRounds = 1;
    // A bilinear sample whose four sensor samples spread over more than this straddles a depth edge: its data
    // weight falls as 1 / (1 + (spread / footprintSigma)^2), so the edge's position comes from the colour
    // image rather than from the interpolation's blur. 0 = off.
    float footprintSigma = 0.0f;
    // Side of the final median window that removes single-pixel outliers: 0 (off), 3 or 5.
    int medianPixels = 3;
    // Instead of that median, a colour-weighted median over (2 radius + 1)^2 pixels when the radius is > 0:
    // each neighbour votes with 1 / (1 + (d / weightedMedianSigma)^2), d its colour distance to the
    // centre, so that a pixel at an edge takes the depth of the side whose colour it has.
    int weightedMedianRadius = 0;
    float weightedMedianSigma = 8.0f;
    // Last, where the measured depths of a pixel's 3 x 3 neighbourhood span more than this (a depth edge,
    // not noise), the pixel takes the nearer of their minimum and maximum: an edge that the smoothing left
    // as a ramp a few pixels wide becomes a step again. 0 = off.
    float edgeSnapRange = 0.0f;
};

// Upsamples a depth map to the size of a colour guide (8-bit, three channels in any order: only distances
// between pixels count) with the dual-guided global smoother (see GlobalSmootherParams). Invalid depth (0,
// NaN, inf, negative) and low-confidence samples carry no data weight: they are filled in from their
// neighbours. The output has depth only where the bilinear upsampling of the measured samples has weight >=
// 0.5 (holes stay holes), confidence as the bilinear map, rounded. Keeps its buffers between frames (a first
// frame, or a new size, allocates them); not thread-safe (it runs its work on the thread pool itself).
class GlobalSmoother {
public:
    GlobalSmoother();
    ~GlobalSmoother();
    GlobalSmoother(GlobalSmoother&&) noexcept;
    GlobalSmoother& operator=(GlobalSmoother&&) noexcept;

    frame::DepthData upsample(const frame::DepthData& depth, ColorView guide,
                              const GlobalSmootherParams& params);

private:
    struct Buffers;
    std::unique_ptr<Buffers> buffers_;
};

} // namespace dc::processing
