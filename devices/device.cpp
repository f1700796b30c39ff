#include "devices/device.h"

namespace dc::devices {

const char* toString(DeviceState state) {
    switch (state) {
    case DeviceState::Closed:
        return "closed";
    case DeviceState::Open:
        return "open";
    case DeviceState::Streaming:
        return "streaming";
    case DeviceState::Stopped:
        return "stopped";
    case DeviceState::Disconnected:
        return "disconnected";
    case DeviceState::Stalled:
        return "stalled";
    }
    return "unknown";
}

Status Device::transitionError(const char* action) const {
    return Error{std::string("cannot ") + action + " " + description() + ": device is " + toString(state_)};
}

Status Device::open() {
    if (state_ != DeviceState::Closed)
        return transitionError("open");
    Status status = doOpen();
    if (status)
        state_ = DeviceState::Open;
    return status;
}

Status Device::start() {
    if (state_ != DeviceState::Open && state_ != DeviceState::Stopped)
        return transitionError("start");
    Status status = doStart();
    if (status)
        state_ = DeviceState::Streaming;
    return status;
}

Status Device::stop() {
    if (state_ == DeviceState::Stopped)
        return {};
    if (state_ != DeviceState::Streaming && state_ != DeviceState::Stalled &&
        state_ != DeviceState::Disconnected)
        return transitionError("stop");
    doStop();
    state_ = DeviceState::Stopped;
    return {};
}

void Device::close() {
    if (state_ == DeviceState::Closed)
        return;
    if (state_ != DeviceState::Open && state_ != DeviceState::Stopped)
        doStop();
    doClose();
    state_ = DeviceState::Closed;
}

CaptureResult Device::capture(std::chrono::milliseconds timeout) {
    if (state_ != DeviceState::Streaming && state_ != DeviceState::Stalled)
        return {CaptureResult::Kind::Error, nullptr, transitionError("capture from").error().message};
    CaptureResult result = doCapture(timeout);
    if (result.kind == CaptureResult::Kind::Frame && result.frame && placement_) {
        auto placed = std::make_shared<frame::Frame>(*result.frame);
        placed->pose = frame::poseFromRigid(
            placed->pose ? frame::compose(*placement_, frame::rigidFromPose(*placed->pose)) : *placement_);
        result.frame = std::move(placed);
    }
    if (result.kind == CaptureResult::Kind::Disconnected)
        state_ = DeviceState::Disconnected;
    else if (result.kind == CaptureResult::Kind::Stalled)
        state_ = DeviceState::Stalled;
    else if (result.kind == CaptureResult::Kind::Frame)
        state_ = DeviceState::Streaming;
    return result;
}

Status Device::reconnect() {
    if (state_ != DeviceState::Disconnected)
        return transitionError("reconnect");
    Status status = doReconnect();
    if (status)
        state_ = DeviceState::Streaming;
    return status;
}

} // namespace dc::devices
