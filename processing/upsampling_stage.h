#pragma once

#include "processing/global_smoother.h"
#include "processing/guided_filter.h"
#include "processing/pipeline.h"
#include "processing/registration.h"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace dc::processing {

// Guided upsampling, to half or the full camera image size and guided by the camera image (its luma for
// the guided filter, its colour for the global smoother), of the depth map that is shown (shownDepth():
// smoothedSceneDepth when selected and present, else sceneDepth); the other map keeps the sensor's
// resolution, since upsampling it too would double the stage's cost for nothing on screen. The cloud then has
// one point per output pixel; intrinsics follow each map's size (Frame::depthIntrinsics() for sceneDepth,
// Intrinsics::scaledTo for the smoothed map). Frames without a camera image pass through.
class UpsamplingStage final : public Stage {
public:
    std::string_view name() const override { return kUpsamplingStage; }
    bool wanted(const ProcessingSettings& settings, const Needs& needs) const override;
    frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings& settings) override;

private:
    // Empty when the image cannot guide (empty or malformed): the frame then passes through.
    std::optional<frame::DepthData> upsample(const frame::DepthData& depth, const frame::CapturedImage& image,
                                             const UpsamplingParams& params);
    // A two-sensor frame's: guided by the colour image aligned to the depth sensor's view.
    std::optional<frame::DepthData> upsampleRegistered(const frame::DepthData& depth,
                                                       const frame::Frame& frame,
                                                       const UpsamplingParams& params);

    GuidedUpsampler upsampler_;
    std::vector<std::uint8_t> lumaScratch_;
    GlobalSmoother smoother_;
    RgbScratch rgbScratch_;
    CameraColourTable colourTable_;
};

// The output size `params` selects for a camera image of width x height.
std::array<int, 2> upsamplingOutputSize(int cameraWidth, int cameraHeight, const UpsamplingParams& params);

// The guided filter's parameters for frames in meters.
GuidedFilterParams guidedFilterParams(const UpsamplingParams& params);

// The global smoother's parameters (Global or Quality, as params.method says) for an upsampling by `factor`
// (output width over sensor width), in the units of depthNoise (meters for frames: depthNoiseMeters).
// Tuned on the four public noisy-Middlebury scenes, x2 to x16, where the noise is 5 disparity levels.
GlobalSmootherParams globalSmootherParams(const UpsamplingParams& params, double factor, float depthNoise);

} // namespace dc::processing
