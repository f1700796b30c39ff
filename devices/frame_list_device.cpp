#include "devices/frame_list_device.h"
#include "base/clock.h"

namespace dc::devices {

FrameListDevice::FrameListDevice(std::vector<frame::FramePtr> frames, double fps, std::string description)
    : frames_(std::move(frames)), fps_(fps), description_(std::move(description)) {}

Capabilities FrameListDevice::capabilities() const {
    if (frames_.empty() || !frames_.front())
        return {};
    const frame::Frame& f = *frames_.front();
    return {.sceneDepth = f.sceneDepth.has_value(),
            .smoothedSceneDepth = f.smoothedSceneDepth.has_value(),
            .confidence = f.sceneDepth && !f.sceneDepth->confidence.empty(),
            .color = !f.capturedImage.empty(),
            .pose = f.pose.has_value(),
            .nominalFps = fps_};
}

Status FrameListDevice::doOpen() {
    if (frames_.empty())
        return Error{description_ + ": no frames to play"};
    for (const frame::FramePtr& f : frames_)
        if (!f)
            return Error{description_ + ": the frame list holds an empty frame"};
    if (!(fps_ > 0.0))
        return Error{description_ + ": frame rate must be positive"};
    return {};
}

Status FrameListDevice::doStart() {
    pacer_.setRate(fps_);
    pacer_.restart();
    return {};
}

CaptureResult FrameListDevice::doCapture(std::chrono::milliseconds timeout) {
    if (!pacer_.waitForNext(timeout))
        return {CaptureResult::Kind::Timeout, nullptr, {}};
    auto frame = std::make_shared<frame::Frame>(*frames_[sequence_ % frames_.size()]);
    frame->sequence = sequence_++;
    frame->timestampNs = base::monotonicNowNs();
    return {CaptureResult::Kind::Frame, std::move(frame), {}};
}

} // namespace dc::devices
