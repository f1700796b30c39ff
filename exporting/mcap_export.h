#pragma once

#include "base/expected.h"
#include "exporting/mcap_writer.h"
#include "frame/frame.h"
#include "frame/jpeg_codec.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>

namespace dc::exporting {

// The topics a frame becomes, named as the ROS 2 RealSense wrapper (realsense2_camera, camera name and
// namespace "camera") publishes them, so a user's tools and launch files find them where they look.
enum class McapTopic {
    DepthImage,
    DepthInfo,
    ColorImage,
    ColorInfo,
    InfraredImage,
    InfraredInfo,
    Tf,
    TfStatic
};
inline constexpr std::size_t kMcapTopicCount = 8;
const char* topicName(McapTopic topic);

// Frames written as ROS 2 messages into an MCAP file (profile ros2, CDR messages, zstd chunks, summary and
// indexes), each stamped with the frame's timestamp (header stamp and log time alike):
//  - depth: sensor_msgs/msg/Image, 16UC1 in millimetres (REP 118) when every sample of the frame is a whole
//    millimetre up to 65.535 m, as a RealSense's Z16 is, else 32FC1 in meters, so no depth is rounded;
//    0 is no measurement either way;
//  - the colour image as rgb8 (converted from NV12, YUYV or JPEG), when the frame has one;
//  - the infrared image as mono8 when all its values fit 8 bits, else mono16, when the frame has one;
//  - each image's sensor_msgs/msg/CameraInfo (K, plumb_bob distortion from the frame's lens);
//  - the pose, when known, as tf2_msgs/msg/TFMessage on /tf: camera_depth_optical_frame (OpenCV axes, as
//    ROS's optical frames) in odom (REP 105's frame for a drifting visual-odometry world such as ARKit's);
//  - a two-sensor frame's extrinsics, once, on /tf_static: camera_color_optical_frame in
//    camera_depth_optical_frame, so a reader places the colour camera as the calibration does.
class McapFrameWriter {
public:
    static Expected<std::unique_ptr<McapFrameWriter>> create(const std::string& path, bool overwrite);

    // A frame without depth is refused (the caller skips it).
    Status add(const frame::Frame& frame);
    Status finish() { return writer_->finish(); }
    std::uint64_t messageCount() const { return writer_->messageCount(); }

private:
    explicit McapFrameWriter(std::unique_ptr<McapWriter> writer) : writer_(std::move(writer)) {}
    // The topic's channel, added (with its schema) on first use so the file lists only what it holds.
    std::uint16_t channel(McapTopic topic);
    Status write(McapTopic topic, std::int64_t stampNs, const std::vector<std::uint8_t>& message);
    Status addColor(const frame::Frame& frame);
    Status addInfrared(const frame::Frame& frame);
    Status addExtrinsics(const frame::Frame& frame);

    std::unique_ptr<McapWriter> writer_;
    std::array<std::uint16_t, kMcapTopicCount> channels_{};
    std::array<std::uint16_t, 3> schemas_{}; // Image, CameraInfo, TFMessage
    frame::JpegDecoder jpeg_;
    bool extrinsicsWritten_ = false;
};

} // namespace dc::exporting
