#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

// ROS 2 messages serialised as ROS 2 records them: little-endian XCDR1 (plain CDR) behind its 4-byte
// encapsulation header, and each type's ros2msg definition for an MCAP schema. Written here rather than
// shared with devices/ros (the reader) so that a mistake in one is caught by the other in the round trip,
// and because exporting/ may not depend on the ROS build.
namespace dc::exporting::ros2 {

// builtin_interfaces/Time, from a nanosecond stamp (negative stamps are clamped to 0: ROS time has no sign).
struct Stamp {
    std::int32_t sec = 0;
    std::uint32_t nanosec = 0;
};
Stamp stampOf(std::int64_t ns);

struct Header {
    Stamp stamp;
    std::string frameId;
};

// sensor_msgs/msg/Image. `data` holds rows of `step` bytes, little-endian pixels.
struct Image {
    Header header;
    std::uint32_t height = 0;
    std::uint32_t width = 0;
    std::string encoding;
    std::uint32_t step = 0;
    std::vector<std::uint8_t> data;
};

// sensor_msgs/msg/CameraInfo of a pinhole camera: R is identity and P = [K | 0] (an unrectified stream
// that is its own rectified view, as the RealSense wrapper publishes its depth).
struct CameraInfo {
    Header header;
    std::uint32_t height = 0;
    std::uint32_t width = 0;
    std::string distortionModel = "plumb_bob";
    std::vector<double> d;
    std::array<double, 9> k{}; // row-major
};

// geometry_msgs/msg/TransformStamped: the pose of `childFrameId` in `header.frameId`.
struct TransformStamped {
    Header header;
    std::string childFrameId;
    std::array<double, 3> translation{};
    std::array<double, 4> rotation{0, 0, 0, 1}; // quaternion x y z w
};

std::vector<std::uint8_t> serialize(const Image& image);
std::vector<std::uint8_t> serialize(const CameraInfo& info);
// tf2_msgs/msg/TFMessage holding these transforms.
std::vector<std::uint8_t> serializeTf(const std::vector<TransformStamped>& transforms);

// A type's name and its ros2msg schema: its definition, then each type it uses after a separator line of
// 80 '=' and "MSG: package/Type" (the name the fields use, without "/msg/": Foxglove's parser resolves
// fields by that exact name), as rosbag2 writes them and Foxglove, rerun and ros2 bag parse them.
struct MessageType {
    const char* name;
    const char* definition;
};
extern const MessageType kImageType;
extern const MessageType kCameraInfoType;
extern const MessageType kTfMessageType;

// A unit quaternion (x y z w) of a proper row-major rotation matrix.
std::array<double, 4> quaternionOf(const std::array<double, 9>& rotation);

} // namespace dc::exporting::ros2
