#include "devices/ros/compressed_image.h"

#include "frame/jpeg_codec.h"
#include "frame/png_codec.h"
#include "frame/rgb_image.h"

#include <cstring>
#include <limits>
#include <span>

namespace dc::devices::ros {

namespace {

// compressed_depth_image_transport writes a 12-byte header before the PNG: its compression format (an
// int32 enum), then two float32s that map 32FC1 depth to 16-bit inverse depth, depth = a / (value - b).
constexpr std::size_t kDepthHeaderBytes = 12;

bool startsWith(const std::string& text, const char* prefix) {
    return text.rfind(prefix, 0) == 0;
}

RosImage imageOf(std::string encoding, const cv::Mat& pixels) {
    RosImage image;
    image.encoding = std::move(encoding);
    image.width = static_cast<std::uint32_t>(pixels.cols);
    image.height = static_cast<std::uint32_t>(pixels.rows);
    image.step = static_cast<std::uint32_t>(pixels.cols * pixels.elemSize());
    image.data.resize(static_cast<std::size_t>(image.step) * image.height);
    for (int y = 0; y < pixels.rows; ++y)
        std::memcpy(image.data.data() + static_cast<std::size_t>(y) * image.step, pixels.ptr(y), image.step);
    return image;
}

// 32FC1 meters from the transport's inverse-depth quantisation of them.
RosImage metersFromInverse(const cv::Mat& quantised, float a, float b) {
    cv::Mat meters(quantised.size(), CV_32FC1);
    for (int y = 0; y < quantised.rows; ++y)
        for (int x = 0; x < quantised.cols; ++x) {
            const float v = quantised.at<std::uint16_t>(y, x);
            meters.at<float>(y, x) = v == 0.0f ? std::numeric_limits<float>::quiet_NaN() : a / (v - b);
        }
    return imageOf("32FC1", meters);
}

Expected<RosImage> decompressDepth(const std::string& format, std::span<const std::uint8_t> data) {
    if (format.find("rvl") != std::string::npos || format.find("RVL") != std::string::npos)
        return Error{"compressedDepth in RVL is not read (only PNG): '" + format + "'"};
    if (data.size() < kDepthHeaderBytes)
        return Error{"a compressedDepth image of " + std::to_string(data.size()) + " bytes has no header"};
    auto png = frame::decodePng(data.subspan(kDepthHeaderBytes));
    if (!png)
        return Error{"compressedDepth: " + png.error().message};
    if (png->type() != CV_16UC1)
        return Error{"compressedDepth: the PNG is not 16-bit gray"};
    if (startsWith(format, "16UC1") || startsWith(format, "mono16"))
        return imageOf("16UC1", *png);
    if (startsWith(format, "32FC1")) {
        float quantisation[2];
        std::memcpy(quantisation, data.data() + 4, sizeof quantisation); // little-endian, as recorded
        return metersFromInverse(*png, quantisation[0], quantisation[1]);
    }
    return Error{"compressedDepth of '" + format + "' is not read (only 16UC1 and 32FC1)"};
}

Expected<RosImage> decompressPng(std::span<const std::uint8_t> data) {
    auto png = frame::decodePng(data);
    if (!png)
        return png.error();
    switch (png->type()) {
    case CV_8UC1:
        return imageOf("mono8", *png);
    case CV_8UC3:
        return imageOf("rgb8", *png);
    case CV_8UC4:
        return imageOf("rgba8", *png);
    case CV_16UC1:
        return imageOf("16UC1", *png);
    default:
        return Error{"a compressed PNG of gray with alpha or 16-bit colour is not read"};
    }
}

Expected<RosImage> decompressJpeg(std::span<const std::uint8_t> data) {
    frame::JpegDecoder decoder;
    const auto size = decoder.size(data);
    if (!size)
        return size.error();
    auto image = decoder.decode(data, size->first, size->second);
    if (!image)
        return image.error();
    const std::vector<std::uint8_t> rgb = frame::toRgb24(*image);
    const cv::Mat pixels(image->height, image->width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data()));
    return imageOf("rgb8", pixels);
}

} // namespace

Expected<RosImage> decompressImage(const std::string& format, const std::uint8_t* bytes, std::size_t size) {
    const std::span<const std::uint8_t> data(bytes, size);
    if (format.find("compressedDepth") != std::string::npos)
        return decompressDepth(format, data);
    if (frame::looksLikePng(data))
        return decompressPng(data);
    auto jpeg = decompressJpeg(data);
    if (!jpeg)
        return Error{"a compressed image ('" + format +
                     "') is neither PNG nor readable JPEG: " + jpeg.error().message};
    return jpeg;
}

} // namespace dc::devices::ros
