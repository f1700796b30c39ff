#pragma once

#include "base/expected.h"
#include "devices/ros/ros_messages.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices::ros {

// A recorded set of ROS topics, random access by topic and message number: a ROS 1 bag (BagReader) or a
// ROS 2 recording (McapStore). The replay of camera topics (bag_source.cpp) pairs, calibrates and decodes
// through this alone, so both formats replay alike. Must stay valid C++17 (the ROS 1 glue includes it).
// Not thread-safe.
class MessageStore {
public:
    struct Topic {
        std::string name;
        std::string type; // in ROS 1 spelling: "sensor_msgs/Image", also for ROS 2's sensor_msgs/msg/Image
    };

    virtual ~MessageStore() = default;

    // What the file is, for descriptions: "ROS bag", "MCAP".
    virtual std::string formatName() const = 0;
    virtual const std::vector<Topic>& topics() const = 0;
    // A topic's type, empty where the store has no such topic.
    std::string typeOf(const std::string& topic) const {
        for (const Topic& t : topics())
            if (t.name == topic)
                return t.type;
        return {};
    }
    // What opening recovered from (a truncated file), for the replay's warnings.
    virtual std::vector<std::string> warnings() const { return {}; }
    // The messages of `topic` in recorded order, kept as an index for random access; returns its handle.
    virtual Expected<std::size_t> indexTopic(const std::string& topic) = 0;
    virtual std::size_t messageCount(std::size_t handle) const = 0;
    virtual std::int64_t recordedNs(std::size_t handle, std::size_t i) const = 0; // the receive time
    virtual Expected<RosImage> image(std::size_t handle, std::size_t i) const = 0;
    // An image's header stamp; a format that can read it without the pixels overrides this.
    virtual Expected<std::int64_t> imageStampNs(std::size_t handle, std::size_t i) const {
        auto decoded = image(handle, i);
        if (!decoded)
            return decoded.error();
        return decoded->stampNs;
    }

    // The first message of a topic, when it exists and has that type.
    virtual std::optional<RosImage> firstImage(const std::string& topic) const = 0;
    virtual std::optional<RosCameraInfo> firstCameraInfo(const std::string& topic) const = 0;
    // RealSense's ROS 1 recordings only (their depth units and extrinsics).
    virtual std::optional<float> firstFloat32(const std::string&) const { return std::nullopt; }
    virtual std::optional<RosTransform> firstTransform(const std::string&) const { return std::nullopt; }
    // A tf2_msgs/TFMessage (/tf, /tf_static): ROS 2 recordings' (readsTransforms()); others are not read.
    virtual bool readsTransforms() const { return false; }
    virtual Expected<std::vector<RosTransformStamped>> transforms(std::size_t, std::size_t) const {
        return Error{formatName() + " recordings' tf messages are not read"};
    }

protected:
    MessageStore() = default;
};

} // namespace dc::devices::ros
