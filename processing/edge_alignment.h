#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/depth_quality.h"

#include <cstddef>

// How well a two-sensor camera's colour lies on its depth (issue 29): the distance between the silhouettes
// the depth map shows and the edges the colour image shows, over the ROI. A registration that is off by a
// calibration error moves every colour edge off its depth edge by about the same amount.
namespace dc::processing {

struct EdgeAlignmentParams {
    // A depth edge: two measured 4-neighbours whose depths differ by more than the larger of minJumpMeters
    // and relativeJump x the nearer depth. 2 cm is several times a good sensor's noise up close; 3 % keeps
    // the noise of far surfaces (which grows with distance) and a slanted floor's depth gradient from
    // reading as edges.
    float minJumpMeters = 0.02f;
    float relativeJump = 0.03f;
    // Canny's hysteresis thresholds on the colour image's luminance (full-range BT.601, 0-255), written as
    // the height of a sharp step whose gradient just reaches them. 20 levels is a boundary a person sees at
    // once and about 8 standard deviations of a webcam's noise after the 3x3 Sobel; an edge found that way
    // is followed through weaker stretches down to 8 levels (shading and low contrast along one object).
    double cannyHighStepLevels = 20.0;
    double cannyLowStepLevels = 8.0;
    // A depth edge with no colour edge within this distance (pixels) is unmatched: its colour edge is missing
    // (same colour in front and behind) and the nearest edge is another object's, which would say nothing
    // about registration.
    double maxSearchPx = 10.0;
};

struct EdgeAlignment {
    // Over the matched depth-edge pixels: the distance to the nearest colour edge, pixels, and converted to
    // millimetres at each pixel's own depth (px x z / fx).
    double medianPx = 0.0;
    double meanPx = 0.0;
    double medianMm = 0.0;
    std::size_t depthEdgePixels = 0; // in the ROI, scored (not beside unseen colour)
    std::size_t matched = 0;         // with a colour edge within maxSearchPx
    double matchedFraction() const {
        return depthEdgePixels ? static_cast<double>(matched) / static_cast<double>(depthEdgePixels) : 0.0;
    }
};

// The colour-to-depth alignment of one frame. `colourOnDepth` is the colour image seen from the depth sensor
// at the depth map's size (colourAlignedToDepth), `depthIntrinsics` the depth map's own (fx converts pixels
// to millimetres).
//
// A depth-edge pixel is the NEARER side of a jump (the foreground's silhouette, where that object's colour
// edge belongs); a sample without a measurement (0, NaN, inf) never forms one, so the border of a hole is
// not an edge. Distances are measured between the edges' positions, not pixel centres: the depth edge lies
// halfway to the farther neighbour, and each Canny pixel is moved along its gradient to the peak of the
// gradient's magnitude (a parabola through it and its two neighbours). At pixel centres a perfectly
// registered sharp edge would read 0 px where the object lies left of or above it and 1 px on its other
// sides (Canny marks the first pixel of a step), half a pixel of bias against a bound of about one.
//
// The colour camera's unseen pixels (exactly kUnseenGray in all three channels) have no colour edge of their
// own: colour edges and depth edges within 2 px of one are dropped, since a gray region's border would read
// as an edge and a depth edge beside it (the colour camera's occlusion shadow lies beside silhouettes) has
// its colour edge hidden. A real pixel of exactly that gray drops a few edges, never moves one.
//
// The region is `polygon`'s samples within `roi` (its bounds, as QualityParams holds them), or all of `roi`
// for an empty polygon. Colour edges are found in the whole image, so an edge just outside the region counts.
// Errors: sizes that differ, intrinsics that are not the depth map's or not valid, an ROI outside the image,
// bad parameters; and, prefixed with kNotEnoughSamples, no depth edge in the region or none matched.
Expected<EdgeAlignment> measureEdgeAlignment(const frame::Plane<float>& depthMeters,
                                             const RgbImage& colourOnDepth,
                                             const frame::Intrinsics& depthIntrinsics, const Roi& roi,
                                             const Polygon& polygon, const EdgeAlignmentParams& params = {});
// Over the whole rectangle.
inline Expected<EdgeAlignment> measureEdgeAlignment(const frame::Plane<float>& depthMeters,
                                                    const RgbImage& colourOnDepth,
                                                    const frame::Intrinsics& depthIntrinsics, const Roi& roi,
                                                    const EdgeAlignmentParams& params = {}) {
    return measureEdgeAlignment(depthMeters, colourOnDepth, depthIntrinsics, roi, Polygon{}, params);
}

} // namespace dc::processing
