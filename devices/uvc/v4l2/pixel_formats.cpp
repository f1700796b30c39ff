#include "devices/uvc/v4l2/pixel_formats.h"

#include "frame/jpeg_codec.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <linux/videodev2.h>

namespace dc::devices::v4l2 {

static_assert(std::endian::native == std::endian::little, "Z16/Y16 buffers are little-endian");

namespace {

// Copies `rows` rows of `rowBytes` each from a buffer with `stride` bytes per row into `out`.
void copyRows(const std::uint8_t* src, std::size_t stride, std::size_t rowBytes, int rows,
              std::uint8_t* out) {
    if (stride == rowBytes) {
        std::memcpy(out, src, rowBytes * static_cast<std::size_t>(rows));
        return;
    }
    for (int y = 0; y < rows; ++y)
        std::memcpy(out + rowBytes * static_cast<std::size_t>(y), src + stride * static_cast<std::size_t>(y),
                    rowBytes);
}

frame::CapturedImage makeImage(frame::PixelFormat format, int width, int height,
                               std::vector<std::uint8_t> bytes) {
    return {format, width, height, std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
}

// MJPEG stays compressed here: the capture thread only checks the header's size, and the frame processor
// decodes the image when something shows it.
Expected<frame::CapturedImage> keepMjpeg(std::span<const std::uint8_t> raw, int width, int height) {
    if (raw.empty())
        return Error{"empty MJPEG frame"};
    thread_local frame::JpegDecoder decoder;
    const auto size = decoder.size(raw);
    if (!size)
        return Error{"MJPEG frame is not a JPEG image"};
    if (size->first != width || size->second != height)
        return Error{"MJPEG frame of " + std::to_string(size->first) + "x" + std::to_string(size->second) +
                     " in a " + std::to_string(width) + "x" + std::to_string(height) + " stream"};
    return makeImage(frame::PixelFormat::Jpeg, width, height, {raw.begin(), raw.end()});
}

frame::CapturedImage greyToNv12(const std::uint8_t* src, std::size_t stride, int width, int height) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, width, height),
                                    128);
    copyRows(src, stride, static_cast<std::size_t>(width), height, bytes.data());
    return makeImage(frame::PixelFormat::Nv12, width, height, std::move(bytes));
}

} // namespace

FormatRole roleOf(std::uint32_t fourcc) {
    switch (fourcc) {
    case V4L2_PIX_FMT_Z16:
    case V4L2_PIX_FMT_Y16:
        return FormatRole::Depth;
    case V4L2_PIX_FMT_YUYV:
    case V4L2_PIX_FMT_NV12:
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_RGB24:
        return FormatRole::Color;
    case V4L2_PIX_FMT_GREY:
        return FormatRole::Guide;
    default:
        return FormatRole::Other;
    }
}

const char* toString(FormatRole role) {
    switch (role) {
    case FormatRole::Depth:
        return "depth";
    case FormatRole::Color:
        return "color";
    case FormatRole::Guide:
        return "infrared";
    case FormatRole::Other:
        return "other";
    }
    return "other";
}

std::string fourccToString(std::uint32_t fourcc) {
    std::string text(4, ' ');
    for (int i = 0; i < 4; ++i) {
        const auto c = static_cast<char>((fourcc >> (8 * i)) & 0xff);
        text[static_cast<std::size_t>(i)] = (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return text;
}

std::optional<std::uint32_t> parseFourcc(const std::string& text) {
    if (text.empty() || text.size() > 4)
        return std::nullopt;
    std::uint32_t fourcc = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        const char c = i < text.size() ? text[i] : ' ';
        if (c < 0x20 || c >= 0x7f)
            return std::nullopt;
        const char upper = (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
        fourcc |= static_cast<std::uint32_t>(static_cast<unsigned char>(upper)) << (8 * i);
    }
    return fourcc;
}

std::size_t minimumFrameBytes(std::uint32_t fourcc, int width, int height, std::uint32_t bytesPerLine) {
    const auto w = static_cast<std::size_t>(width);
    const auto h = static_cast<std::size_t>(height);
    switch (fourcc) {
    case V4L2_PIX_FMT_Z16:
    case V4L2_PIX_FMT_Y16:
        return std::max<std::size_t>(bytesPerLine, 2 * w) * h;
    case V4L2_PIX_FMT_YUYV:
        return std::max<std::size_t>(bytesPerLine, 4 * ((w + 1) / 2)) * h;
    case V4L2_PIX_FMT_RGB24:
        return std::max<std::size_t>(bytesPerLine, 3 * w) * h;
    case V4L2_PIX_FMT_GREY:
        return std::max<std::size_t>(bytesPerLine, w) * h;
    case V4L2_PIX_FMT_NV12: // luma rows, then half as many chroma rows of the same stride
        return std::max<std::size_t>(bytesPerLine, w) * (h + (h + 1) / 2);
    default:
        return 0;
    }
}

void depthToMeters(std::span<const std::uint8_t> raw, int width, int height, std::uint32_t bytesPerLine,
                   float metersPerUnit, frame::Plane<float>& out) {
    if (out.width != width || out.height != height ||
        out.pixels.size() != static_cast<std::size_t>(width) * height)
        out = frame::Plane<float>(width, height);
    const std::size_t stride = std::max<std::size_t>(bytesPerLine, 2 * static_cast<std::size_t>(width));
    // OpenCV's SIMD conversion computes raw * scale in float, exactly as a scalar loop would, 2-3x faster.
    const cv::Mat source(height, width, CV_16UC1, const_cast<std::uint8_t*>(raw.data()), stride);
    cv::Mat meters(height, width, CV_32FC1, out.pixels.data());
    source.convertTo(meters, CV_32F, static_cast<double>(metersPerUnit));
}

Expected<frame::CapturedImage> toCapturedImage(std::uint32_t fourcc, std::span<const std::uint8_t> raw,
                                               int width, int height, std::uint32_t bytesPerLine) {
    const auto w = static_cast<std::size_t>(width);
    const std::size_t needed = minimumFrameBytes(fourcc, width, height, bytesPerLine);
    if (needed > raw.size())
        return Error{"short " + fourccToString(fourcc) + " frame: " + std::to_string(raw.size()) + " of " +
                     std::to_string(needed) + " bytes"};
    auto rowCopy = [&](frame::PixelFormat format, std::size_t rowBytes, int rows) {
        std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(format, width, height));
        copyRows(raw.data(), std::max<std::size_t>(bytesPerLine, rowBytes), rowBytes, rows, bytes.data());
        return makeImage(format, width, height, std::move(bytes));
    };
    switch (fourcc) {
    case V4L2_PIX_FMT_YUYV:
        return rowCopy(frame::PixelFormat::Yuyv, 4 * ((w + 1) / 2), height);
    case V4L2_PIX_FMT_RGB24:
        return rowCopy(frame::PixelFormat::Rgb24, 3 * w, height);
    case V4L2_PIX_FMT_NV12:
        // Chroma rows of `width` bytes (interleaved Cb/Cr at half resolution) need an even size.
        if (width % 2 != 0 || height % 2 != 0)
            return Error{"NV12 frame of odd size " + std::to_string(width) + "x" + std::to_string(height)};
        return rowCopy(frame::PixelFormat::Nv12, w, height + height / 2);
    case V4L2_PIX_FMT_GREY:
        return greyToNv12(raw.data(), std::max<std::size_t>(bytesPerLine, w), width, height);
    case V4L2_PIX_FMT_MJPEG:
        return keepMjpeg(raw, width, height);
    default:
        return Error{"unsupported camera image format '" + fourccToString(fourcc) + "'"};
    }
}

} // namespace dc::devices::v4l2
