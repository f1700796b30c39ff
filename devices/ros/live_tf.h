#pragma once

#include "base/expected.h"
#include "devices/ros/ros_messages.h"

#include <cstdint>
#include <memory>
#include <string>

// Compiled as C++17 (tf2's headers include Debian's ROS 1 messages); this header must stay valid C++17.
namespace dc::devices::ros {

// A live /tf and /tf_static (tf2's buffer, the last 10 s), for the pose of a camera's frame at an image's
// stamp, whichever middleware delivered the transforms. Thread-safe: transforms are added on a subscription's
// thread and looked up on the capture thread.
class LiveTf {
public:
    explicit LiveTf(std::string fixedFrame);
    ~LiveTf();
    LiveTf(const LiveTf&) = delete;
    LiveTf& operator=(const LiveTf&) = delete;

    void add(const RosTransformStamped& transform, bool isStatic);
    // Where `frameId` is in the fixed frame at `stampNs` (p_fixed = R p + t). /tf comes on its own
    // connection, so the transform at an image's stamp can arrive just after the image: while /tf keeps pace
    // with the images it is waited for a little. A camera whose /tf is slower (or a pose published once)
    // takes the newest transform at once, but never one newer than the image: that pose is another moment's.
    // Fails in one line when the frames are not connected, or when no fixed frame was asked for.
    Expected<RosTransform> transform(const std::string& frameId, std::int64_t stampNs) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace dc::devices::ros
