#include "devices/synthetic/synthetic_device.h"
#include "base/clock.h"

namespace dc::devices {

Status checkSyntheticConfig(const SyntheticConfig& c) {
    const auto sideOk = [](int s) { return s >= 1 && s <= kSyntheticMaxImageSide; };
    if (!sideOk(c.depthWidth) || !sideOk(c.depthHeight) || !sideOk(c.cameraWidth) || !sideOk(c.cameraHeight))
        return Error{"synthetic source: sizes must be between 1 and " +
                     std::to_string(kSyntheticMaxImageSide) + " pixels"};
    if (static_cast<std::int64_t>(c.depthWidth) * c.depthHeight > kSyntheticMaxDepthPixels)
        return Error{"synthetic source: depth " + std::to_string(c.depthWidth) + "x" +
                     std::to_string(c.depthHeight) + " is larger than the limit of " +
                     std::to_string(kSyntheticMaxDepthPixels) + " pixels (1920x1440)"};
    if (!(c.fps > 0.0 && c.fps <= kSyntheticMaxFps))
        return Error{"synthetic source: frame rate must be in (0, 1000] fps"};
    return {};
}

SyntheticDevice::SyntheticDevice(SyntheticConfig config)
    : config_(config), scene_(config.seed),
      cameraIntrinsics_(SyntheticScene::cameraIntrinsics(config.cameraWidth, config.cameraHeight)) {}

std::string SyntheticDevice::description() const {
    return "synthetic " + std::to_string(config_.depthWidth) + "x" + std::to_string(config_.depthHeight) +
           "@" + std::to_string(static_cast<int>(config_.fps + 0.5)) + (config_.motion ? " (moving)" : "");
}

Capabilities SyntheticDevice::capabilities() const {
    return {.sceneDepth = true,
            .smoothedSceneDepth = false,
            .confidence = true,
            .color = true,
            .pose = true,
            .monotonicTimestamps = true};
}

Status SyntheticDevice::doOpen() {
    if (Status s = checkSyntheticConfig(config_); !s)
        return s;
    if (!config_.motion)
        staticImage_ = scene_.renderImage(cameraIntrinsics_, SyntheticScene::cameraPose(0.0, false));
    return {};
}

Status SyntheticDevice::doStart() {
    pacer_.setRate(config_.fps);
    pacer_.restart();
    return {};
}

CaptureResult SyntheticDevice::doCapture(std::chrono::milliseconds timeout) {
    if (config_.paced && !pacer_.waitForNext(timeout))
        return {CaptureResult::Kind::Timeout, nullptr, {}};
    const std::uint64_t sequence = sequence_++;
    const double t = static_cast<double>(sequence) / config_.fps;
    return {CaptureResult::Kind::Frame, makeFrame(sequence, t), {}};
}

frame::FramePtr SyntheticDevice::makeFrame(std::uint64_t sequence, double timeSeconds) const {
    auto frame = std::make_shared<frame::Frame>();
    frame->sequence = sequence;
    frame->timestampNs = base::monotonicNowNs();
    const frame::Pose pose = SyntheticScene::cameraPose(timeSeconds, config_.motion);
    frame->pose = pose;
    frame->cameraIntrinsics = cameraIntrinsics_;
    frame->capturedImage = config_.motion ? scene_.renderImage(cameraIntrinsics_, pose) : staticImage_;
    const frame::Intrinsics depthK = cameraIntrinsics_.scaledTo(config_.depthWidth, config_.depthHeight);
    if (config_.noise) {
        frame->sceneDepth = scene_.sensorDepth(depthK, pose, sequence);
    } else {
        frame::DepthData exact{scene_.trueDepth(depthK, pose),
                               frame::Plane<std::uint8_t>(depthK.width, depthK.height)};
        for (std::size_t i = 0; i < exact.depthMeters.pixels.size(); ++i)
            exact.confidence.pixels[i] = static_cast<std::uint8_t>(
                exact.depthMeters.pixels[i] > 0.0f ? frame::Confidence::High : frame::Confidence::Low);
        frame->sceneDepth = std::move(exact);
    }
    return frame;
}

} // namespace dc::devices
