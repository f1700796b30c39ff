#pragma once

#include "base/expected.h"
#include "devices/ros/ros_messages.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

// ROS 2 messages as DDS serializes them: XCDR1 (plain CDR) with its 4-byte encapsulation header, little or
// big endian, into the plain values the ROS 1 readers produce, so both replay through the same code.
namespace dc::devices::ros {

// Reads one CDR-encoded message. Alignment counts from the end of the encapsulation header, as XCDR1
// says; a read past the end, or an unsupported encapsulation, sets failed() and yields zeros.
class CdrReader {
public:
    explicit CdrReader(std::span<const std::uint8_t> message);

    bool failed() const { return failed_; }
    // Why the message could not be read, once failed().
    const std::string& problem() const { return problem_; }

    std::uint8_t u8();
    std::uint32_t u32();
    std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
    double f64();
    std::string string();
    // A sequence<uint8>: its length, then the bytes (a view into the message).
    std::span<const std::uint8_t> bytes();
    // A header's stamp (builtin_interfaces/Time) in nanoseconds.
    std::int64_t stampNs();

private:
    void fail(const std::string& why);
    bool take(std::size_t size, std::size_t alignment);
    std::uint64_t swapped(std::uint64_t v, std::size_t size) const;

    std::span<const std::uint8_t> data_;
    std::size_t pos_ = 4;
    bool bigEndian_ = false;
    bool failed_ = false;
    std::string problem_;
};

// sensor_msgs/msg/Image.
Expected<RosImage> decodeImage(std::span<const std::uint8_t> message);
// sensor_msgs/msg/CompressedImage, decompressed (devices/ros/compressed_image.h).
Expected<RosImage> decodeCompressedImage(std::span<const std::uint8_t> message);
// The decoder of a topic's images by its type in ROS 1 spelling: CompressedImage's, or Image's.
using ImageDecoder = Expected<RosImage> (*)(std::span<const std::uint8_t>);
ImageDecoder imageDecoderFor(const std::string& type);
// Only the header stamp of any message that starts with std_msgs/Header (an image, without its pixels).
Expected<std::int64_t> decodeHeaderStampNs(std::span<const std::uint8_t> message);
// sensor_msgs/msg/CameraInfo: size, distortion and K.
Expected<RosCameraInfo> decodeCameraInfo(std::span<const std::uint8_t> message);
// tf2_msgs/msg/TFMessage: every transform it holds.
Expected<std::vector<RosTransformStamped>> decodeTfMessage(std::span<const std::uint8_t> message);

} // namespace dc::devices::ros
