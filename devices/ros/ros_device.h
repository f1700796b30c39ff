#pragma once

#include "devices/device.h"
#include "devices/frame_pairer.h"
#include "devices/ros/ros_link.h"
#include "devices/ros/ros_messages.h"
#include "devices/ros/ros_source_spec.h"
#include "frame/frame.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace dc::devices::ros {

// A depth camera published on ROS 1 or ROS 2 topics: sensor_msgs/Image depth (16UC1 in millimetres, 32FC1
// in meters), an optional colour image, and the depth camera's camera_info for the intrinsics. The link's
// thread (roscpp's spinner, or the DDS readers', one per device) only copies each message into a small inbox;
// the capture thread converts, pairs depth with colour by header stamp within the tolerance, and builds
// frames. The link is checked once a second (ROS 1: the master answers; ROS 2: the depth publisher is still
// matched): when the camera cannot be heard the device is Disconnected, and reconnect() succeeds once it is
// back. Timestamps are the images' header stamps (ROS time, the publisher's wall clock). With a fixed frame,
// each frame's pose is the depth image's frame in it, from /tf at the image's stamp.
class RosDevice final : public Device {
public:
    RosDevice(RosSourceConfig config, std::unique_ptr<RosLink> link);
    ~RosDevice() override;

    std::string description() const override;
    Capabilities capabilities() const override;
    void interruptCapture() override;

    const RosSourceConfig& config() const { return config_; }
    const FramePairer& pairer() const { return pairer_; }

protected:
    Status doOpen() override;
    Status doStart() override;
    void doStop() override;
    void doClose() override;
    CaptureResult doCapture(std::chrono::milliseconds timeout) override;
    Status doReconnect() override;

private:
    struct DepthMessage {
        RosImage image;
    };
    struct ColorMessage {
        RosImage image;
    };
    struct Problem {
        std::string message;
    };
    using Message = std::variant<DepthMessage, ColorMessage, RosCameraInfo, Problem>;

    SubscriptionCallbacks callbacks();
    void restartStreams();
    Status subscribe();
    void post(Message message);
    std::deque<Message> waitForMessages(std::chrono::milliseconds timeout);
    std::optional<CaptureResult> take(Message& message);
    std::optional<CaptureResult> takeDepth(RosImage& image);
    std::optional<CaptureResult> takeColor(RosImage& image);
    void takeInfo(const RosCameraInfo& info);
    std::optional<CaptureResult> checkLink();
    std::optional<CaptureResult> checkWatchdog();
    std::optional<CaptureResult> report(std::string message);
    std::optional<frame::Intrinsics> intrinsicsFor(int width, int height);
    std::optional<frame::Pose> poseAt(std::int64_t stampNs);
    frame::FramePtr makeFrame(PairedCapture capture);
    std::optional<CaptureResult> nextFrame();

    RosSourceConfig config_;
    // What the link subscribes to; whether the images are compressed is the link's finding at open.
    SubscriptionTopics topics_;
    std::unique_ptr<RosLink> link_;
    std::mutex inboxMutex_;
    std::condition_variable inboxReady_;
    std::deque<Message> inbox_; // guarded by inboxMutex_
    bool interrupted_ = false;  // guarded by inboxMutex_
    FramePairer pairer_{0};
    std::optional<StampedDepth> depthOnly_;   // the newest depth image when there is no colour topic
    std::optional<frame::Intrinsics> depthK_; // from camera_info, at camera_info's size
    bool warnedApproximate_ = false;
    std::string lastProblem_; // reported once until something else happens
    std::string lastPoseProblem_;
    std::string depthFrameId_; // header.frame_id of the newest depth image: the camera's frame in /tf
    std::int64_t lastDepthStampNs_ = 0;
    std::uint64_t depthSequence_ = 0;
    std::uint64_t colorSequence_ = 0;
    std::uint64_t sequence_ = 0;
    std::chrono::steady_clock::time_point startedAt_{};
    std::chrono::steady_clock::time_point lastFrame_{};
    std::chrono::steady_clock::time_point lastLinkCheck_{};
    bool stalled_ = false;
};

} // namespace dc::devices::ros
