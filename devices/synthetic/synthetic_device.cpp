#include "devices/synthetic/synthetic_device.h"
#include "base/clock.h"
#include "base/log.h"
#include "base/mutex.h"
#include "base/worker.h"

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace dc::devices {

// Worker threads that render frames `sequence` .. `sequence + ahead - 1` ahead of the capture thread,
// which takes them in order. At most `ahead` frames exist at once, so a consumer that stops taking costs
// no more than that.
class SyntheticDevice::RenderAhead {
public:
    RenderAhead(const SyntheticDevice& device, std::uint64_t first, int threads)
        : device_(device), nextToRender_(first), nextToTake_(first),
          ahead_(static_cast<std::size_t>(threads) + 1) {
        for (int i = 0; i < threads; ++i)
            threads_.emplace_back("synthetic rendering stopped", [this] { work(); });
    }
    ~RenderAhead() {
        {
            base::MutexLock lock(mutex_);
            stopping_ = true;
        }
        space_.notify_all();
        for (base::Worker& t : threads_)
            t.join();
    }
    RenderAhead(const RenderAhead&) = delete;
    RenderAhead& operator=(const RenderAhead&) = delete;

    // The frame `sequence` (the one after the last taken) once rendered; nullptr when it is not ready
    // within `timeout` or interrupt() was called.
    std::shared_ptr<frame::Frame> take(std::uint64_t sequence, std::chrono::milliseconds timeout) {
        base::MutexLock lock(mutex_);
        lock.waitFor(ready_, timeout,
                     [&]() DC_REQUIRES(mutex_) { return interrupted_ || done_.contains(sequence); });
        interrupted_ = false;
        const auto found = done_.find(sequence);
        if (found == done_.end())
            return nullptr;
        auto frame = std::move(found->second);
        done_.erase(found);
        nextToTake_ = sequence + 1;
        lock.unlock();
        space_.notify_all();
        return frame;
    }

    void interrupt() {
        {
            base::MutexLock lock(mutex_);
            interrupted_ = true;
        }
        ready_.notify_all();
    }

private:
    void work() {
        base::MutexLock lock(mutex_);
        for (;;) {
            lock.wait(space_, [&]() DC_REQUIRES(mutex_) {
                return stopping_ || nextToRender_ < nextToTake_ + ahead_;
            });
            if (stopping_)
                return;
            const std::uint64_t sequence = nextToRender_++;
            lock.unlock();
            auto frame = device_.renderFrame(sequence, static_cast<double>(sequence) / device_.config_.fps);
            lock.lock();
            done_.emplace(sequence, std::move(frame));
            ready_.notify_all();
        }
    }

    const SyntheticDevice& device_;
    base::Mutex mutex_;
    std::condition_variable ready_; // a frame was rendered, or interrupt()
    std::condition_variable space_; // a frame was taken, or stopping
    std::map<std::uint64_t, std::shared_ptr<frame::Frame>> done_ DC_GUARDED_BY(mutex_);
    std::uint64_t nextToRender_ DC_GUARDED_BY(mutex_);
    std::uint64_t nextToTake_ DC_GUARDED_BY(mutex_);
    const std::size_t ahead_;
    bool stopping_ DC_GUARDED_BY(mutex_) = false;
    bool interrupted_ DC_GUARDED_BY(mutex_) = false;
    std::vector<base::Worker> threads_;
};

namespace {

// The flat target's camera image: uniform mid grey.
frame::CapturedImage greyImage(int width, int height) {
    const std::size_t size = frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, width, height);
    return {frame::PixelFormat::Nv12, width, height,
            std::make_shared<const std::vector<std::uint8_t>>(size, std::uint8_t{128})};
}

} // namespace

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
    if (const auto& t = c.flatTarget) {
        if (!(t->distanceMeters > 0.0 && t->distanceMeters <= SyntheticScene::kMaxRangeMeters))
            return Error{"synthetic source: plane distance must be in (0, 5] m"};
        if (!(std::abs(t->tiltDegrees) <= kFlatTargetMaxTiltDegrees))
            return Error{"synthetic source: plane tilt must be within 85 degrees of facing the camera"};
        if (!(t->noiseMm >= 0.0 && t->noiseMm <= kFlatTargetMaxNoiseMm))
            return Error{"synthetic source: plane noise must be in [0, 100] mm"};
    }
    if (c.view && (c.motion || c.flatTarget))
        return Error{
            "synthetic source: view= places a still camera in the desk scene, not with motion or plane="};
    return {};
}

SyntheticConfig syntheticRigConfig() {
    SyntheticConfig config;
    const frame::RigCalibration rig = syntheticRigCalibration();
    config.depthWidth = rig.depth.intrinsics.width;
    config.depthHeight = rig.depth.intrinsics.height;
    config.cameraWidth = rig.colour.intrinsics.width;
    config.cameraHeight = rig.colour.intrinsics.height;
    config.fps = 30.0;
    config.rig = true;
    return config;
}

SyntheticDevice::SyntheticDevice(SyntheticConfig config)
    : config_(config), scene_(config.seed),
      cameraIntrinsics_(SyntheticScene::cameraIntrinsics(config.cameraWidth, config.cameraHeight)) {
    if (config_.rig) {
        rig_ = std::make_shared<const frame::RigCalibration>(syntheticRigCalibration());
        cameraIntrinsics_ = rig_->colour.intrinsics.scaledTo(config.cameraWidth, config.cameraHeight);
    }
}

SyntheticDevice::~SyntheticDevice() = default;

std::string SyntheticDevice::description() const {
    return "synthetic " + std::to_string(config_.depthWidth) + "x" + std::to_string(config_.depthHeight) +
           "@" + std::to_string(static_cast<int>(config_.fps + 0.5)) + (config_.motion ? " (moving)" : "") +
           (config_.rig ? ", two-sensor rig" : "") + (config_.flatTarget ? ", flat target" : "");
}

Capabilities SyntheticDevice::capabilities() const {
    return {.sceneDepth = true,
            .smoothedSceneDepth = false,
            .confidence = true,
            .color = true,
            .pose = true,
            .monotonicTimestamps = true,
            .nominalFps = config_.fps};
}

void SyntheticDevice::interruptCapture() {
    if (renderAhead_)
        renderAhead_->interrupt();
}

Status SyntheticDevice::doOpen() {
    if (Status s = checkSyntheticConfig(config_); !s)
        return s;
    if (rig_ && colourCamera_.directions.empty())
        colourCamera_ = lensCamera({cameraIntrinsics_, rig_->colour.lens});
    if (config_.flatTarget)
        staticImage_ = greyImage(cameraIntrinsics_.width, cameraIntrinsics_.height);
    else if (!config_.motion)
        staticImage_ = renderImage(poseAt(0.0));
    return {};
}

Status SyntheticDevice::doStart() {
    pacer_.setRate(config_.fps);
    pacer_.restart();
    // Two workers keep a moving 640x480 scene at 60 fps on a machine with two free cores (each frame takes
    // about 13 ms of CPU there); more would only compete with the consumers for the same cores.
    const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 2);
    renderAhead_ = std::make_unique<RenderAhead>(*this, sequence_, threads);
    return {};
}

void SyntheticDevice::doStop() {
    renderAhead_.reset();
    pending_.reset();
}

CaptureResult SyntheticDevice::doCapture(std::chrono::milliseconds timeout) {
    if (!pending_)
        pending_ = renderAhead_->take(sequence_, timeout);
    if (!pending_ || (config_.paced && !pacer_.waitForNext(timeout)))
        return {CaptureResult::Kind::Timeout, nullptr, {}};
    ++sequence_;
    pending_->timestampNs = base::monotonicNowNs(); // the moment it is delivered, as a camera's would be
    return {CaptureResult::Kind::Frame, std::move(pending_), {}};
}

frame::FramePtr SyntheticDevice::makeFrame(std::uint64_t sequence, double timeSeconds) const {
    return renderFrame(sequence, timeSeconds);
}

frame::Pose SyntheticDevice::poseAt(double timeSeconds) const {
    const frame::Pose usual = SyntheticScene::cameraPose(timeSeconds, config_.motion);
    if (!config_.view)
        return usual;
    return frame::poseFromRigid(frame::compose(frame::rigidFromPose(usual), *config_.view));
}

std::shared_ptr<frame::Frame> SyntheticDevice::renderFrame(std::uint64_t sequence, double timeSeconds) const {
    auto frame = std::make_shared<frame::Frame>();
    frame->sequence = sequence;
    frame->timestampNs = base::monotonicNowNs();
    const frame::Pose pose = poseAt(timeSeconds);
    frame->pose = pose;
    frame->cameraIntrinsics = cameraIntrinsics_;
    frame->rig = rig_;
    frame->capturedImage = config_.motion && !config_.flatTarget ? renderImage(pose) : staticImage_;
    const frame::Intrinsics depthK = depthIntrinsics();
    if (config_.flatTarget) {
        frame->sceneDepth =
            flatTargetDepth(depthK, *config_.flatTarget, config_.noise, config_.seed, sequence);
    } else if (config_.noise) {
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

// The colour sensor's image: the one camera's own, or the rig's colour sensor beside the depth sensor.
frame::CapturedImage SyntheticDevice::renderImage(const frame::Pose& depthPose) const {
    if (!rig_)
        return scene_.renderImage(cameraIntrinsics_, depthPose);
    return scene_.renderImage(colourCamera_, colourSensorPose(depthPose, rig_->depthToColour));
}

frame::Intrinsics SyntheticDevice::depthIntrinsics() const {
    return (rig_ ? rig_->depth.intrinsics : cameraIntrinsics_)
        .scaledTo(config_.depthWidth, config_.depthHeight);
}

} // namespace dc::devices
