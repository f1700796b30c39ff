#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

// The ROS messages depthcloud reads, as plain values. Debian's generated ROS 1 message headers use
// std::allocator<void>::rebind, which C++20 removed, so only the glue files (compiled as C++17, see
// CMakeLists.txt) include ROS; everything else sees these. This header must stay valid C++17.
namespace dc::devices::ros {

// sensor_msgs/Image.
struct RosImage {
    std::int64_t stampNs = 0; // header.stamp
    std::string frameId;
    std::string encoding;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t step = 0; // bytes per row, padding included
    bool bigEndian = false;
    std::vector<std::uint8_t> data;
};

// sensor_msgs/CameraInfo: the parts that place points.
struct RosCameraInfo {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::array<double, 9> k{}; // row-major camera matrix
    std::string distortionModel;
    std::vector<double> d;
};

// geometry_msgs/Transform.
struct RosTransform {
    std::array<double, 3> translationMeters{};
    std::array<double, 4> rotationXyzw{0, 0, 0, 1};
};

// geometry_msgs/TransformStamped, as tf2_msgs/TFMessage carries a list of them: the pose of `childFrameId`
// in `parentFrameId` at `stampNs`.
struct RosTransformStamped {
    std::int64_t stampNs = 0;
    std::string parentFrameId;
    std::string childFrameId;
    RosTransform transform;
};

} // namespace dc::devices::ros
