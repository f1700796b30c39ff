#include "devices/ros/ros_device.h"

#include "base/log.h"
#include "devices/replay/replay_source.h"
#include "devices/ros/ros_image.h"
#include "frame/calibration.h"

#include <algorithm>
#include <cstdio>

namespace dc::devices::ros {

namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr auto kLinkCheckInterval = 1s; // how soon a camera that cannot be heard shows as Disconnected
constexpr auto kInfoGrace = 1s;         // depth waits this long for camera_info before a guessed lens
constexpr std::size_t kMaxInbox = 8;    // messages the capture thread has not taken yet; oldest dropped

std::string seconds(std::chrono::milliseconds ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", static_cast<double>(ms.count()) / 1000.0);
    return text;
}

} // namespace

RosDevice::RosDevice(RosSourceConfig config, std::unique_ptr<RosLink> link)
    : config_(std::move(config)), topics_{config_.depthTopic, config_.colorTopic, config_.infoTopic,
                                          config_.fixedFrame},
      link_(std::move(link)) {}

// The link's thread posts into the inbox: it goes first.
RosDevice::~RosDevice() {
    link_.reset();
}

std::string RosDevice::description() const {
    return std::string(config_.ros2 ? "ROS 2 " : "ROS ") + config_.depthTopic +
           (config_.colorTopic.empty() ? "" : " + " + config_.colorTopic);
}

Capabilities RosDevice::capabilities() const {
    Capabilities c;
    c.sceneDepth = true;
    c.color = !config_.colorTopic.empty();
    c.reconnects = true;
    c.pose = !config_.fixedFrame.empty();
    c.realtimeTimestamps = true;
    return c;
}

void RosDevice::interruptCapture() {
    {
        const std::lock_guard lock(inboxMutex_);
        interrupted_ = true;
    }
    inboxReady_.notify_all();
}

Status RosDevice::doOpen() {
    if (Status s = link_->open(topics_); !s)
        return s;
    logInfo(description() + ": " + link_->where() + ", camera_info " + config_.infoTopic);
    return {};
}

void RosDevice::post(Message message) {
    {
        const std::lock_guard lock(inboxMutex_);
        inbox_.push_back(std::move(message));
        while (inbox_.size() > kMaxInbox)
            inbox_.pop_front();
    }
    inboxReady_.notify_all();
}

SubscriptionCallbacks RosDevice::callbacks() {
    return {
        [this](RosImage image) { post(DepthMessage{std::move(image)}); },
        [this](RosImage image) { post(ColorMessage{std::move(image)}); },
        [this](RosCameraInfo info) { post(std::move(info)); },
        [this](std::string problem) { post(Problem{std::move(problem)}); },
    };
}

void RosDevice::restartStreams() {
    pairer_ = FramePairer(std::chrono::nanoseconds(config_.pairTolerance).count());
    depthOnly_.reset();
    lastDepthStampNs_ = 0;
    startedAt_ = lastFrame_ = lastLinkCheck_ = Clock::now();
    stalled_ = false;
}

Status RosDevice::subscribe() {
    link_->unsubscribe();
    {
        const std::lock_guard lock(inboxMutex_);
        inbox_.clear();
    }
    if (Status s = link_->subscribe(topics_, callbacks()); !s)
        return s;
    restartStreams();
    return {};
}

Status RosDevice::doStart() {
    return subscribe();
}

void RosDevice::doStop() {
    link_->unsubscribe();
    pairer_.reset();
    depthOnly_.reset();
}

void RosDevice::doClose() {
    link_->unsubscribe();
}

Status RosDevice::doReconnect() {
    if (Status s = link_->reconnect(topics_, callbacks()); !s)
        return s;
    restartStreams();
    logInfo(description() + ": " + link_->where() + " is back; streaming again");
    return {};
}

std::optional<CaptureResult> RosDevice::checkLink() {
    if (Clock::now() - lastLinkCheck_ < kLinkCheckInterval)
        return std::nullopt;
    lastLinkCheck_ = Clock::now();
    const Status alive = link_->alive();
    if (alive)
        return std::nullopt;
    pairer_.reset();
    depthOnly_.reset();
    return CaptureResult{CaptureResult::Kind::Disconnected, nullptr, alive.error().message};
}

std::optional<CaptureResult> RosDevice::checkWatchdog() {
    const auto silent = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - lastFrame_);
    if (stalled_ || silent < config_.watchdog)
        return std::nullopt;
    stalled_ = true;
    return CaptureResult{CaptureResult::Kind::Stalled, nullptr,
                         "no frame from " + config_.depthTopic + " for " + seconds(silent)};
}

// A problem that repeats with every message is reported once, not thirty times a second, until another
// problem replaces it.
std::optional<CaptureResult> RosDevice::report(std::string message) {
    if (message == lastProblem_)
        return std::nullopt;
    lastProblem_ = message;
    return CaptureResult{CaptureResult::Kind::Error, nullptr, std::move(message)};
}

std::deque<RosDevice::Message> RosDevice::waitForMessages(std::chrono::milliseconds timeout) {
    std::unique_lock lock(inboxMutex_);
    inboxReady_.wait_for(lock, timeout, [this] { return !inbox_.empty() || interrupted_; });
    interrupted_ = false;
    return std::exchange(inbox_, {});
}

std::optional<CaptureResult> RosDevice::takeDepth(RosImage& image) {
    auto depth = depthFromImage(image, kRosDepthMetersPerUnit);
    if (!depth)
        return report(config_.depthTopic + ": " + depth.error().message);
    const std::int64_t previous = std::exchange(lastDepthStampNs_, image.stampNs);
    if (image.stampNs != 0 && image.stampNs < previous) {
        // Images stamped before the jump can never pair with those after it.
        pairer_.reset();
        return report(config_.depthTopic + ": the publisher's clock jumped back " +
                      std::to_string((previous - image.stampNs) / 1'000'000) + " ms; pairing starts again");
    }
    depthFrameId_ = image.frameId;
    StampedDepth stamped{++depthSequence_, image.stampNs, std::move(*depth)};
    if (config_.colorTopic.empty())
        depthOnly_ = std::move(stamped); // nothing to wait for
    else
        pairer_.pushDepth(std::move(stamped));
    return std::nullopt;
}

std::optional<CaptureResult> RosDevice::takeColor(RosImage& image) {
    auto color = colorFromImage(image);
    if (!color)
        return report(config_.colorTopic + ": " + color.error().message);
    pairer_.pushColor({++colorSequence_, image.stampNs, std::move(*color)});
    return std::nullopt;
}

void RosDevice::takeInfo(const RosCameraInfo& info) {
    auto record = cameraInfoRecord(info);
    if (record)
        depthK_ = record->intrinsics;
    else
        (void)report(config_.infoTopic + ": " + record.error().message);
}

std::optional<CaptureResult> RosDevice::take(Message& message) {
    if (auto* depth = std::get_if<DepthMessage>(&message))
        return takeDepth(depth->image);
    if (auto* color = std::get_if<ColorMessage>(&message))
        return takeColor(color->image);
    if (auto* problem = std::get_if<Problem>(&message))
        return report(std::move(problem->message));
    takeInfo(std::get<RosCameraInfo>(message));
    return std::nullopt;
}

// The depth lens from camera_info; without one after kInfoGrace, a field-of-view guess, said once.
std::optional<frame::Intrinsics> RosDevice::intrinsicsFor(int width, int height) {
    if (depthK_)
        return depthK_->scaledTo(width, height);
    if (Clock::now() - startedAt_ < kInfoGrace)
        return std::nullopt;
    if (!warnedApproximate_) {
        warnedApproximate_ = true;
        logWarning(description() + ": no camera_info on " + config_.infoTopic +
                   "; approximate geometry from a default field of view");
    }
    return frame::intrinsicsFromFieldOfView(width, height, kRosFallbackFovDegrees);
}

// The camera's pose from /tf when a fixed frame was asked for; a missing transform is said once and the
// frame goes on without a pose.
std::optional<frame::Pose> RosDevice::poseAt(std::int64_t stampNs) {
    if (config_.fixedFrame.empty())
        return std::nullopt;
    auto t = link_->transform(depthFrameId_, stampNs);
    if (!t) {
        if (t.error().message != lastPoseProblem_)
            logWarning(description() + ": " + t.error().message);
        lastPoseProblem_ = t.error().message;
        return std::nullopt;
    }
    lastPoseProblem_.clear();
    return replay::poseFromQuaternion(t->translationMeters.data(), t->rotationXyzw.data());
}

frame::FramePtr RosDevice::makeFrame(PairedCapture capture) {
    const int w = capture.depth.depthMeters.width;
    const int h = capture.depth.depthMeters.height;
    const auto k = intrinsicsFor(w, h);
    if (!k)
        return nullptr;
    auto frame = std::make_shared<frame::Frame>();
    frame->sequence = sequence_++;
    frame->timestampNs = capture.depth.timestampNs;
    frame->cameraIntrinsics = *k;
    if (capture.color) {
        // One set of intrinsics per frame, as for a registered sensor: the depth camera's places the points.
        frame->capturedImage = std::move(capture.color->image);
        frame->cameraIntrinsics = k->scaledTo(frame->capturedImage.width, frame->capturedImage.height);
    }
    frame->sceneDepth = frame::DepthData{std::move(capture.depth.depthMeters), {}};
    frame->pose = poseAt(capture.depth.timestampNs);
    return frame;
}

std::optional<CaptureResult> RosDevice::nextFrame() {
    for (;;) {
        std::optional<PairedCapture> capture = pairer_.pop();
        if (!capture && depthOnly_)
            capture = PairedCapture{std::move(*std::exchange(depthOnly_, std::nullopt)), std::nullopt};
        if (!capture)
            return std::nullopt;
        if (frame::FramePtr frame = makeFrame(std::move(*capture))) {
            lastFrame_ = Clock::now();
            stalled_ = false;
            return CaptureResult{CaptureResult::Kind::Frame, std::move(frame), {}};
        }
    }
}

CaptureResult RosDevice::doCapture(std::chrono::milliseconds timeout) {
    if (auto gone = checkLink())
        return *gone;
    if (auto frame = nextFrame())
        return *frame;
    if (auto stalled = checkWatchdog())
        return *stalled;
    // Bounded so that the link is checked on time even when the caller waits long.
    std::deque<Message> messages = waitForMessages(std::min<std::chrono::milliseconds>(timeout, 100ms));
    std::optional<CaptureResult> problem;
    for (Message& message : messages)
        if (auto p = take(message); p && !problem)
            problem = std::move(p);
    if (problem)
        return *problem;
    if (auto frame = nextFrame())
        return *frame;
    return {CaptureResult::Kind::Timeout, nullptr, {}};
}

} // namespace dc::devices::ros
