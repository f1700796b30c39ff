#include "processing/upsampling_stage.h"

#include <algorithm>
#include <cmath>
#include <optional>

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

GlobalSmootherParams globalSmootherParams(const UpsamplingParams& params, double factor, float depthNoise) {
    const float s = std::max(params.smoothness, 0.0f);
    const float noise = std::max(depthNoise, 0.0f);
    const auto f = static_cast<float>(std::max(factor, 1.0));
    GlobalSmootherParams p;
    p.footprintSigma = 0.2f * noise;
    p.medianPixels = 3;
    if (params.method == UpsamplingMethod::Quality) {
        p.sensorColor = {6.0f * s, 2, 24.0f, 0.0f};
        p.sensorDepth = {10.0f * s, 3, 0.0f, 0.4f * noise};
        // The output passes bridge the band of about `factor` pixels that interpolation blurs at an edge:
        // the colour pass's reach grows with it.
        p.outputColor = {3.0f * s * std::pow(f, 2.5f), 3, 4.0f, 0.0f};
        p.outputDepth = {100.0f * s * std::sqrt(f), 3, 64.0f, 0.2f * noise};
        // A 3 x 3 range of 6 noise sigmas is an edge (what noise leaves after smoothing spans far less).
        p.edgeSnapRange = 6.0f * noise;
        return p;
    }
    // Real time: the sweeps that buy the least error left out, so that it runs faster than OpenCV's fast
    // global smoother at every factor (MAD on the four scenes about 4 % above the quality mode's passes
    // with one sweep each): one colour and one depth sweep at the sensor, and at the output a single pass
    // whose colour term, stronger than the quality mode's guard, does what the colour pass did there.
    p.sensorColor = {6.0f * s, 1, 24.0f, 0.0f};
    p.sensorDepth = {15.0f * s, 1, 0.0f, 0.4f * noise};
    // Beyond x4 the interpolated depth says less about where an edge runs, and the colour term, tightened
    // with the factor, says more (tuned at x8 and x16).
    const float colorSigma = 32.0f * std::min(1.0f, std::pow(4.0f / f, 0.7f));
    p.outputDepth = {100.0f * s * std::sqrt(f), 1, colorSigma, 0.24f * noise};
    return p;
}

bool UpsamplingStage::wanted(const ProcessingSettings& settings, const Needs& needs) const {
    return settings.upsampling && needs.anyDepth();
}

std::optional<frame::DepthData> UpsamplingStage::upsample(const frame::DepthData& depth,
                                                          const frame::CapturedImage& image,
                                                          const UpsamplingParams& params) {
    const auto [width, height] = upsamplingOutputSize(image.width, image.height, params);
    if (params.method == UpsamplingMethod::Global || params.method == UpsamplingMethod::Quality) {
        const ColorView guide = cameraRgbView(image, width, height, rgbScratch_);
        if (guide.empty())
            return std::nullopt;
        const double factor = static_cast<double>(width) / std::max(depth.depthMeters.width, 1);
        return smoother_.upsample(depth, guide,
                                  globalSmootherParams(params, factor, params.depthNoiseMeters));
    }
    const GrayView luma = lumaView(image, lumaScratch_);
    if (luma.empty())
        return std::nullopt;
    upsampler_.setGuide(luma, width, height, guidedFilterParams(params));
    return upsampler_.upsample(depth);
}

// The camera image of a two-sensor frame shows the scene from elsewhere: as a guide it would put colour
// edges beside the depth edges they belong to. The guide is therefore the colour image aligned to the depth
// sensor, and the output keeps the depth sensor's view and shape (width from the camera image as for one
// camera), so the depth intrinsics scaled to it still place every point.
std::optional<frame::DepthData> UpsamplingStage::upsampleRegistered(const frame::DepthData& depth,
                                                                    const frame::Frame& frame,
                                                                    const UpsamplingParams& params) {
    const frame::CapturedImage& image = frame.capturedImage;
    const int sensorWidth = depth.depthMeters.width, sensorHeight = depth.depthMeters.height;
    if (image.empty() || sensorWidth <= 0 || sensorHeight <= 0)
        return std::nullopt;
    const int width = upsamplingOutputSize(image.width, image.height, params)[0];
    const int height =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(width) * sensorHeight / sensorWidth)));
    const RgbImage guide = colourAlignedToDepth(frame, depth.depthMeters, width, height, colourTable_);
    if (guide.empty())
        return std::nullopt;
    if (params.method == UpsamplingMethod::Global || params.method == UpsamplingMethod::Quality) {
        const ColorView view{guide.pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3};
        const double factor = static_cast<double>(width) / sensorWidth;
        return smoother_.upsample(depth, view, globalSmootherParams(params, factor, params.depthNoiseMeters));
    }
    // Full-range BT.601 luma, as the camera's own Y plane that guides one camera.
    lumaScratch_.resize(guide.pixels.size() / 3);
    for (std::size_t i = 0; i < lumaScratch_.size(); ++i)
        lumaScratch_[i] = static_cast<std::uint8_t>(std::lround(
            0.299 * guide.pixels[i * 3] + 0.587 * guide.pixels[i * 3 + 1] + 0.114 * guide.pixels[i * 3 + 2]));
    upsampler_.setGuide(GrayView{lumaScratch_.data(), width, height, width}, width, height,
                        guidedFilterParams(params));
    return upsampler_.upsample(depth);
}

frame::FramePtr UpsamplingStage::process(frame::FramePtr frame, const ProcessingSettings& settings) {
    if (!frame || !frame->sceneDepth)
        return frame;
    const bool smoothed = showsSmoothed(*frame, settings.depthSource);
    const frame::DepthData& depth = smoothed ? *frame->smoothedSceneDepth : *frame->sceneDepth;
    const bool registered = frame->rig && !isSingleCamera(*frame->rig);
    auto upsampled = registered ? upsampleRegistered(depth, *frame, settings.upsamplingParams)
                                : upsample(depth, frame->capturedImage, settings.upsamplingParams);
    if (!upsampled)
        return frame;
    auto out = std::make_shared<frame::Frame>(*frame);
    (smoothed ? out->smoothedSceneDepth : out->sceneDepth) = std::move(*upsampled);
    return out;
}

} // namespace dc::processing
