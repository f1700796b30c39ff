// Compiled as C++17: includes Debian's ROS 1 headers (ros_messages.h says why).
#include "devices/ros/live_tf.h"

#include "devices/ros/ros_conversions.h"

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace dc::devices::ros {

namespace {

constexpr double kTfCacheSeconds = 10.0;
// How long an image waits for the transform at its stamp: a few messages' transit on a loaded machine.
constexpr std::chrono::milliseconds kTfWait{100};

::ros::Time rosTime(std::int64_t ns) {
    ::ros::Time t;
    t.fromNSec(static_cast<std::uint64_t>(ns));
    return t;
}

// tf2's messages span lines; ours are one.
std::string oneLine(std::string text) {
    for (char& c : text)
        if (c == '\n')
            c = ' ';
    while (!text.empty() && text.back() == ' ')
        text.pop_back();
    return text;
}

geometry_msgs::TransformStamped toMessage(const RosTransformStamped& t) {
    geometry_msgs::TransformStamped m;
    m.header.stamp = rosTime(t.stampNs);
    m.header.frame_id = t.parentFrameId;
    m.child_frame_id = t.childFrameId;
    const auto& [x, y, z] = t.transform.translationMeters;
    m.transform.translation.x = x;
    m.transform.translation.y = y;
    m.transform.translation.z = z;
    const auto& q = t.transform.rotationXyzw;
    m.transform.rotation.x = q[0];
    m.transform.rotation.y = q[1];
    m.transform.rotation.z = q[2];
    m.transform.rotation.w = q[3];
    return m;
}

} // namespace

struct LiveTf::Impl {
    std::string fixedFrame;
    tf2::BufferCore tf{::ros::Duration(kTfCacheSeconds)};
    // /tf kept pace with the images last time (its transform at the image's stamp came): worth waiting for.
    std::atomic<bool> tfKeepsPace{true};
};

LiveTf::LiveTf(std::string fixedFrame) : impl_(std::make_unique<Impl>()) {
    impl_->fixedFrame = std::move(fixedFrame);
}

LiveTf::~LiveTf() = default;

void LiveTf::add(const RosTransformStamped& transform, bool isStatic) {
    try {
        impl_->tf.setTransform(toMessage(transform), "depthcloud", isStatic);
    } catch (const std::exception&) {
        // A malformed transform (an empty frame id, a NaN) is one tf2 refuses: the rest of /tf still counts.
    }
}

Expected<RosTransform> LiveTf::transform(const std::string& frameId, std::int64_t stampNs) const {
    const std::string& fixed = impl_->fixedFrame;
    if (fixed.empty())
        return Error{"no fixed frame to look poses up in"};
    const ::ros::Time stamp = rosTime(stampNs);
    try {
        const auto wait = impl_->tfKeepsPace ? kTfWait : std::chrono::milliseconds{0};
        const auto giveUp = std::chrono::steady_clock::now() + wait;
        while (true) {
            try {
                auto exact = impl_->tf.lookupTransform(fixed, frameId, stamp);
                impl_->tfKeepsPace = true;
                return toTransform(exact.transform);
            } catch (const tf2::ExtrapolationException&) {
                if (std::chrono::steady_clock::now() >= giveUp)
                    break;
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
            }
        }
        impl_->tfKeepsPace = false;
        const auto latest = impl_->tf.lookupTransform(fixed, frameId, ::ros::Time(0));
        if (latest.header.stamp > stamp)
            return Error{"no pose of " + frameId + " in " + fixed + " at the image's stamp yet"};
        return toTransform(latest.transform);
    } catch (const std::exception& e) {
        return Error{"no pose of " + frameId + " in " + fixed + " from /tf: " + oneLine(e.what())};
    }
}

} // namespace dc::devices::ros
