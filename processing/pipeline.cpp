#include "processing/pipeline.h"

#include "processing/confidence_estimator.h"
#include "processing/smoothing_stage.h"
#include "processing/upsampling_stage.h"

#include <chrono>

namespace dc::processing {

void Pipeline::add(std::unique_ptr<Stage> stage) {
    stages_.push_back(std::move(stage));
}

void Pipeline::reset() {
    for (auto& stage : stages_)
        stage->reset();
}

bool Pipeline::hasStage(std::string_view name) const {
    for (const auto& stage : stages_)
        if (stage->name() == name)
            return true;
    return false;
}

frame::FramePtr Pipeline::run(frame::FramePtr frame, const ProcessingSettings& settings, const Needs& needs) {
    timings_.clear();
    if (!frame)
        return frame;
    const int w = frame->sceneDepth ? frame->sceneDepth->depthMeters.width : 0;
    const int h = frame->sceneDepth ? frame->sceneDepth->depthMeters.height : 0;
    if (w != lastWidth_ || h != lastHeight_) {
        reset();
        lastWidth_ = w;
        lastHeight_ = h;
    }
    for (auto& stage : stages_) {
        if (!stage->wanted(settings, needs))
            continue;
        const auto start = std::chrono::steady_clock::now();
        const frame::FramePtr in = frame;
        frame = stage->process(std::move(frame), settings);
        const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
        // A stage that passed the frame through did no work (sensor confidence needs no estimate).
        if (frame != in)
            timings_.push_back({std::string(stage->name()), took.count()});
    }
    return frame;
}

const frame::DepthData* shownDepth(const frame::Frame& frame, DepthSource source) {
    if (showsSmoothed(frame, source))
        return &*frame.smoothedSceneDepth;
    return frame.sceneDepth ? &*frame.sceneDepth : nullptr;
}

bool showsSmoothed(const frame::Frame& frame, DepthSource source) {
    return source == DepthSource::Smoothed && frame.smoothedSceneDepth.has_value();
}

Pipeline makeDefaultPipeline() {
    Pipeline pipeline;
    pipeline.add(std::make_unique<ConfidenceEstimatorStage>()); // first: later stages read confidence
    // Smoothing at the sensor's resolution, where it is cheap; upsampling last, of what will be shown.
    pipeline.add(std::make_unique<SmoothingStage>());
    pipeline.add(std::make_unique<UpsamplingStage>());
    return pipeline;
}

} // namespace dc::processing
