#include "devices/ros/ros_image.h"

#include "devices/recording/frame_codec.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>

namespace dc::devices::ros {

namespace {

// RealSense records its YUYV colour stream under librealsense's own format name; ROS's "yuv422" is UYVY.
const std::string kYuyvEncodings[] = {"YUYV", "yuv422_yuy2"};

struct PixelLayout {
    int bytesPerPixel = 0;
    int cvType = 0;
};

std::string describe(const RosImage& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height) + " " + image.encoding;
}

// The image's rows, checked against its declared step and size: a message from the wire or a damaged
// bag may claim more than it holds.
Expected<cv::Mat> rowsOf(const RosImage& image, int bytesPerPixel, int cvType) {
    const std::size_t rowBytes = static_cast<std::size_t>(image.width) * bytesPerPixel;
    if (image.width == 0 || image.height == 0)
        return Error{"image " + describe(image) + " is empty"};
    if (image.step < rowBytes || image.data.size() < static_cast<std::size_t>(image.step) * image.height)
        return Error{"image " + describe(image) + " holds " + std::to_string(image.data.size()) +
                     " bytes with a step of " + std::to_string(image.step) + ", too few for its size"};
    return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), cvType,
                   const_cast<std::uint8_t*>(image.data.data()), image.step);
}

std::optional<PixelLayout> colorLayout(const std::string& encoding) {
    if (encoding == "rgb8" || encoding == "bgr8")
        return PixelLayout{3, CV_8UC3};
    if (encoding == "rgba8" || encoding == "bgra8")
        return PixelLayout{4, CV_8UC4};
    if (encoding == "yuv422" || encoding == "YUYV" || encoding == "yuv422_yuy2")
        return PixelLayout{2, CV_8UC2};
    return std::nullopt;
}

} // namespace

ImageKind imageKind(const std::string& encoding) {
    if (encoding == "16UC1" || encoding == "mono16" || encoding == "32FC1")
        return ImageKind::Depth;
    return colorLayout(encoding) ? ImageKind::Color : ImageKind::Other;
}

Expected<frame::Plane<float>> depthFromImage(const RosImage& image, double metersPerUnit) {
    const bool floatMeters = image.encoding == "32FC1";
    if (imageKind(image.encoding) != ImageKind::Depth)
        return Error{"image encoding '" + image.encoding + "' is not depth (16UC1, mono16 or 32FC1)"};
    auto rows = rowsOf(image, floatMeters ? 4 : 2, floatMeters ? CV_32FC1 : CV_16UC1);
    if (!rows)
        return rows.error();
    // The message says how its samples are stored; this machine is little-endian.
    const bool swap = image.bigEndian;
    frame::Plane<float> depth(static_cast<int>(image.width), static_cast<int>(image.height));
    for (int y = 0; y < depth.height; ++y) {
        const std::uint8_t* row = rows->ptr<std::uint8_t>(y);
        float* out = &depth.at(0, y);
        for (int x = 0; x < depth.width; ++x) {
            if (floatMeters) {
                std::uint32_t bits = 0;
                std::memcpy(&bits, row + 4 * x, 4);
                out[x] = std::bit_cast<float>(swap ? __builtin_bswap32(bits) : bits);
            } else {
                std::uint16_t units = 0;
                std::memcpy(&units, row + 2 * x, 2);
                out[x] = recording::depthFromUnits(swap ? __builtin_bswap16(units) : units, metersPerUnit);
            }
        }
    }
    return depth;
}

Expected<frame::CapturedImage> colorFromImage(const RosImage& image) {
    const auto layout = colorLayout(image.encoding);
    if (!layout)
        return Error{"image encoding '" + image.encoding +
                     "' is not a colour encoding depthcloud reads (rgb8, "
                     "bgr8, rgba8, bgra8, YUYV, yuv422)"};
    auto rows = rowsOf(image, layout->bytesPerPixel, layout->cvType);
    if (!rows)
        return rows.error();
    frame::CapturedImage out;
    out.width = static_cast<int>(image.width);
    out.height = static_cast<int>(image.height);
    const bool yuyv = std::find(std::begin(kYuyvEncodings), std::end(kYuyvEncodings), image.encoding) !=
                      std::end(kYuyvEncodings);
    out.format = layout->bytesPerPixel == 2 ? frame::PixelFormat::Yuyv : frame::PixelFormat::Rgb24;
    if (out.format == frame::PixelFormat::Yuyv && out.width % 2 != 0)
        return Error{"image " + describe(image) + " has an odd width, which 4:2:2 cannot have"};
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(
        frame::CapturedImage::byteSize(out.format, out.width, out.height));
    cv::Mat packed(out.height, out.width, out.format == frame::PixelFormat::Yuyv ? CV_8UC2 : CV_8UC3,
                   bytes->data());
    if (image.encoding == "rgb8" || yuyv)
        rows->copyTo(packed);
    else if (image.encoding == "bgr8")
        cv::cvtColor(*rows, packed, cv::COLOR_BGR2RGB);
    else if (image.encoding == "rgba8")
        cv::cvtColor(*rows, packed, cv::COLOR_RGBA2RGB);
    else if (image.encoding == "bgra8")
        cv::cvtColor(*rows, packed, cv::COLOR_BGRA2RGB);
    else // UYVY: each 4-byte group U Y0 V Y1 becomes Y0 U Y1 V
        cv::mixChannels(*rows, packed, std::vector<int>{0, 1, 1, 0});
    out.bytes = std::move(bytes);
    return out;
}

bool isInfraredEncoding(const std::string& encoding) {
    return encoding == "mono8" || encoding == "8UC1" || encoding == "mono16" || encoding == "16UC1";
}

Expected<frame::Plane<std::uint16_t>> infraredFromImage(const RosImage& image) {
    if (!isInfraredEncoding(image.encoding))
        return Error{"image encoding '" + image.encoding + "' is not infrared (mono8, 8UC1, mono16, 16UC1)"};
    const bool wide = image.encoding == "mono16" || image.encoding == "16UC1";
    auto rows = rowsOf(image, wide ? 2 : 1, wide ? CV_16UC1 : CV_8UC1);
    if (!rows)
        return rows.error();
    frame::Plane<std::uint16_t> out(static_cast<int>(image.width), static_cast<int>(image.height));
    for (int y = 0; y < out.height; ++y) {
        const std::uint8_t* row = rows->ptr<std::uint8_t>(y);
        std::uint16_t* dst = &out.at(0, y);
        for (int x = 0; x < out.width; ++x) {
            if (!wide) {
                dst[x] = row[x];
                continue;
            }
            std::uint16_t value = 0;
            std::memcpy(&value, row + 2 * x, 2);
            dst[x] = image.bigEndian ? __builtin_bswap16(value) : value;
        }
    }
    return out;
}

Expected<CameraInfoRecord> cameraInfoRecord(const RosCameraInfo& info) {
    CameraInfoRecord record;
    record.intrinsics = {info.k[0],
                         info.k[4],
                         info.k[2],
                         info.k[5],
                         static_cast<int>(info.width),
                         static_cast<int>(info.height)};
    if (!record.intrinsics.valid())
        return Error{"camera_info K = [" + std::to_string(info.k[0]) + " ... ] at " +
                     std::to_string(info.width) + "x" + std::to_string(info.height) + " cannot place points"};
    record.distortionModel = info.distortionModel;
    record.distortion = info.d;
    return record;
}

std::string withoutTransport(const std::string& topic) {
    for (const std::string suffix : {"/compressedDepth", "/compressed"})
        if (topic.size() > suffix.size() && topic.ends_with(suffix))
            return topic.substr(0, topic.size() - suffix.size());
    return topic;
}

} // namespace dc::devices::ros
