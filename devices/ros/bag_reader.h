#pragma once

#include "base/expected.h"
#include "devices/ros/message_store.h"
#include "devices/ros/ros_messages.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices::ros {

// A ROS 1 bag read through rosbag_storage, behind plain values (ros_messages.h says why). Every rosbag
// exception is caught here and becomes an Error naming the file. Not thread-safe.
class BagReader final : public MessageStore {
public:
    static Expected<std::unique_ptr<BagReader>> open(const std::string& path);
    ~BagReader() override;

    std::string formatName() const override { return "ROS bag"; }
    const std::vector<Topic>& topics() const override;
    Expected<std::size_t> indexTopic(const std::string& topic) override;
    std::size_t messageCount(std::size_t handle) const override;
    std::int64_t recordedNs(std::size_t handle, std::size_t i) const override;
    Expected<RosImage> image(std::size_t handle, std::size_t i) const override;

    std::optional<RosImage> firstImage(const std::string& topic) const override;
    std::optional<RosCameraInfo> firstCameraInfo(const std::string& topic) const override;
    std::optional<float> firstFloat32(const std::string& topic) const override;
    std::optional<RosTransform> firstTransform(const std::string& topic) const override;

private:
    struct Impl;
    explicit BagReader(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// Writes images to a new ROS 1 bag (uncompressed, as RealSense Viewer records), each message at its header
// stamp: the benchmark's peer and a way to hand frames to ROS tools. Not thread-safe.
class BagWriter {
public:
    static Expected<std::unique_ptr<BagWriter>> create(const std::string& path);
    ~BagWriter();

    Status write(const std::string& topic, const RosImage& image);
    Status write(const std::string& topic, std::int64_t stampNs, const RosCameraInfo& info);
    // Writes the index; without it the bag is unreadable.
    Status close();

private:
    struct Impl;
    explicit BagWriter(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace dc::devices::ros
