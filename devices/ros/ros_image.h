#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include "devices/ros/ros_messages.h"

#include <string>
#include <vector>

// sensor_msgs images and camera_info as depthcloud frames: shared by bag replay and the live ROS source.
namespace dc::devices::ros {

// The message type of image topics, in ROS 1 spelling (message stores give ROS 2's in it too).
inline constexpr const char* kRosImageType = "sensor_msgs/Image";
// image_transport's compressed and compressedDepth topics: every message store's image() decompresses them.
inline constexpr const char* kRosCompressedImageType = "sensor_msgs/CompressedImage";
// image_transport publishes an image compressed under its raw topic and the transport's name
// (/camera/color/image_raw/compressed): the raw topic's name, and whether the name has such a suffix.
std::string withoutTransport(const std::string& topic);
inline bool namesCompressedTransport(const std::string& topic) {
    return withoutTransport(topic) != topic;
}
// A depth stream without camera_info is placed with this horizontal field of view: a RealSense depth
// sensor's, the camera ROS users record most.
inline constexpr double kRosFallbackFovDegrees = 87.0;

// What an image topic carries, from its encoding.
enum class ImageKind { Depth, Color, Other };
ImageKind imageKind(const std::string& encoding);

// The depth unit that REP 118 gives each depth encoding: 16UC1 (and RealSense's mono16 Z16) in
// millimetres unless the recording says otherwise, 32FC1 in meters.
inline constexpr double kRosDepthMetersPerUnit = 0.001;

// A depth image in meters; `metersPerUnit` scales 16-bit encodings (32FC1 is meters already).
Expected<frame::Plane<float>> depthFromImage(const RosImage& image, double metersPerUnit);
// A colour image as the frame stores it: YUYV stays packed 4:2:2, the rest becomes packed RGB.
Expected<frame::CapturedImage> colorFromImage(const RosImage& image);

// An infrared image's encoding: 8-bit (mono8, 8UC1) or 16-bit (mono16, 16UC1) single-channel intensity.
bool isInfraredEncoding(const std::string& encoding);
// An infrared image as raw sensor intensity (frame::Frame::infrared): 8-bit values are kept as they are.
Expected<frame::Plane<std::uint16_t>> infraredFromImage(const RosImage& image);

// A stream's lens as camera_info records it, kept whole for two-sensor registration.
struct CameraInfoRecord {
    frame::Intrinsics intrinsics;   // K at width x height
    std::string distortionModel;    // "plumb_bob", "Brown Conrady", "Inverse Brown Conrady", ...
    std::vector<double> distortion; // D, in the model's order (OpenCV's k1 k2 p1 p2 k3 for plumb_bob)
};
// Fails when K cannot place points (zero focal length) or the size is zero.
Expected<CameraInfoRecord> cameraInfoRecord(const RosCameraInfo& info);

} // namespace dc::devices::ros
