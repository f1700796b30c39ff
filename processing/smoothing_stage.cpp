#include "processing/smoothing_stage.h"

namespace dc::processing {

bool SmoothingStage::wanted(const ProcessingSettings& settings, const Needs& needs) const {
    return settings.smoothing && settings.depthSource == DepthSource::Smoothed && needs.anyDepth();
}

void SmoothingStage::reset() {
    smoother_.reset();
    lastTimestampNs_.reset();
}

frame::FramePtr SmoothingStage::process(frame::FramePtr frame, const ProcessingSettings& settings) {
    if (!frame || !frame->sceneDepth || frame->smoothedSceneDepth)
        return frame;
    const std::int64_t t = frame->timestampNs;
    auto out = std::make_shared<frame::Frame>(*frame);
    if (lastTimestampNs_ == t) {
        out->smoothedSceneDepth = smoother_.redo(*frame->sceneDepth, settings.smoothingParams);
        return out;
    }
    if (lastTimestampNs_ && (t < *lastTimestampNs_ || t - *lastTimestampNs_ > kMaxGapNs))
        smoother_.reset();
    lastTimestampNs_ = t;
    out->smoothedSceneDepth = smoother_.smooth(*frame->sceneDepth, settings.smoothingParams);
    return out;
}

} // namespace dc::processing
