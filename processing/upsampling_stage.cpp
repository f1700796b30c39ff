#include "processing/upsampling_stage.h"

#include <algorithm>

namespace dc::processing {

std::array<int, 2> upsamplingOutputSize(int cameraWidth, int cameraHeight, const UpsamplingParams& params) {
    if (params.size == UpsamplingSize::FullCamera)
        return {cameraWidth, cameraHeight};
    return {(cameraWidth + 1) / 2, (cameraHeight + 1) / 2};
}

GuidedFilterParams guidedFilterParams(const UpsamplingParams& params) {
    GuidedFilterParams p;
    p.radius = std::max(params.radiusPixels, 1);
    p.epsilon = params.epsilon;
    p.subsample = params.method == UpsamplingMethod::Full ? 1 : std::clamp(params.subsample, 1, 16);
    p.fitWeighted = params.fitWeighted;
    p.fitNoise = params.fitNoiseMeters;
    return p;
}

bool UpsamplingStage::wanted(const ProcessingSettings& settings, const Needs& needs) const {
    return settings.upsampling && needs.anyDepth();
}

frame::FramePtr UpsamplingStage::process(frame::FramePtr frame, const ProcessingSettings& settings) {
    if (!frame || !frame->sceneDepth)
        return frame;
    const GrayView luma = lumaView(frame->capturedImage, lumaScratch_);
    if (luma.empty())
        return frame;
    const auto [width, height] = upsamplingOutputSize(luma.width, luma.height, settings.upsamplingParams);
    upsampler_.setGuide(luma, width, height, guidedFilterParams(settings.upsamplingParams));
    auto out = std::make_shared<frame::Frame>(*frame);
    if (showsSmoothed(*frame, settings.depthSource))
        out->smoothedSceneDepth = upsampler_.upsample(*frame->smoothedSceneDepth);
    else
        out->sceneDepth = upsampler_.upsample(*frame->sceneDepth);
    return out;
}

} // namespace dc::processing
