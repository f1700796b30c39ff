#pragma once

#include "base/expected.h"
#include "devices/ros/ros_messages.h"

#include <cstddef>
#include <cstdint>
#include <string>

// sensor_msgs/CompressedImage's payload as the plain image an Image message of the same picture carries, so
// that compressed topics replay through the same code. `format` is the message's own field, as the ROS 2
// image_transport plugins write it: "rgb8; jpeg compressed bgr8" or "bgr8; png compressed bgr8" (compressed),
// "16UC1; compressedDepth png" or "32FC1; compressedDepth png" (compressedDepth); older recorders wrote
// only "jpeg" or "png".
namespace dc::devices::ros {

// JPEG becomes rgb8; PNG becomes rgb8, rgba8, mono8 or 16UC1 by its channels and depth; a compressedDepth
// PNG becomes 16UC1, or 32FC1 meters for a 32FC1 source (its inverse-depth quantisation undone; a zero
// sample is NaN, no depth). Malformed data, or a codec other than these (RVL), is an error naming it.
// Pointer and size rather than a span: the ROS 1 bag glue, which is C++17, calls it too.
Expected<RosImage> decompressImage(const std::string& format, const std::uint8_t* data, std::size_t size);

} // namespace dc::devices::ros
