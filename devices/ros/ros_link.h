#pragma once

#include "base/expected.h"
#include "devices/ros/ros_messages.h"

#include <functional>
#include <string>

// What a live ROS camera subscribes to and hears, whichever middleware carries it: ROS 1's master and
// TCPROS (ros_node.h) or ROS 2's DDS (dds_subscription.h). This header must stay valid C++17.
namespace dc::devices::ros {

struct TopicInfo {
    std::string name;
    std::string type; // in ROS 1's spelling: "sensor_msgs/Image", ...
};

struct SubscriptionTopics {
    std::string depth;
    std::string color;      // empty: none
    std::string info;       // the depth camera's camera_info
    std::string fixedFrame; // non-empty: listen to /tf and /tf_static for poses in this frame
    // The image topics carry sensor_msgs/CompressedImage (image_transport's compressed or compressedDepth).
    bool depthCompressed = false;
    bool colorCompressed = false;
};

// Called on the subscription's own thread; they must return quickly and not throw.
struct SubscriptionCallbacks {
    std::function<void(RosImage)> depth;
    std::function<void(RosImage)> color;
    std::function<void(RosCameraInfo)> info;
    // A message that could not be read (a compressed image that does not decode), in one line.
    std::function<void(std::string)> problem;
};

// The middleware under a live ROS camera (RosDevice): connecting, subscribing, knowing whether the camera
// can still be heard, and /tf. Called from the device's capture thread only.
class RosLink {
public:
    virtual ~RosLink() = default;
    // "ROS master http://127.0.0.1:11311", "DDS domain 0".
    virtual std::string where() const = 0;
    // Connects and checks what the topics carry; may decide their transports (compressed or raw).
    virtual Status open(SubscriptionTopics& topics) = 0;
    // Replaces any earlier subscription.
    virtual Status subscribe(const SubscriptionTopics& topics, SubscriptionCallbacks callbacks) = 0;
    virtual void unsubscribe() = 0;
    // Whether the camera can still be heard; an error says why not, and the device shows Disconnected.
    virtual Status alive() = 0;
    // Called while Disconnected: succeeds once the camera can be heard again, subscribed.
    virtual Status reconnect(const SubscriptionTopics& topics, SubscriptionCallbacks callbacks) = 0;
    // Where `frameId` is in the fixed frame at `stampNs` (p_fixed = R p + t), from /tf and /tf_static.
    virtual Expected<RosTransform> transform(const std::string& frameId, std::int64_t stampNs) const = 0;
};

} // namespace dc::devices::ros
