#include "devices/replay/capture_files.h"

#include "base/files.h"
#include "devices/recording/frame_codec.h"
#include "frame/jpeg_codec.h"
#include "frame/png_codec.h"
#include "frame/rgb_image.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace dc::devices::replay {

namespace {

std::string describe(const cv::Mat& m) {
    return std::to_string(m.channels()) + "-channel " + (m.depth() == CV_16U ? "16-bit" : "8-bit") + " image";
}

// A JPEG starts with its start-of-image marker.
bool looksLikeJpeg(std::span<const std::uint8_t> bytes) {
    return bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
}

Expected<frame::CapturedImage> decodeJpeg(std::span<const std::uint8_t> jpeg) {
    frame::JpegDecoder decoder;
    auto size = decoder.size(jpeg);
    if (!size)
        return size.error();
    auto image = decoder.decode(jpeg, size->first, size->second);
    if (!image)
        return image.error();
    return frame::makeRgb24Image(image->width, image->height, frame::toRgb24(*image));
}

Expected<frame::CapturedImage> decodeColor(std::span<const std::uint8_t> bytes) {
    if (looksLikeJpeg(bytes))
        return decodeJpeg(bytes);
    if (!frame::looksLikePng(bytes))
        return Error{"not a PNG or JPEG image"};
    auto rgb = frame::decodePng(bytes, frame::PngPixels::Rgb8);
    if (!rgb)
        return rgb.error();
    const cv::Mat& m = *rgb;
    return frame::makeRgb24Image(m.cols, m.rows, std::vector<std::uint8_t>(m.datastart, m.dataend));
}

} // namespace

Expected<std::string> readTextFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return Error{"cannot open " + path + ": " + std::strerror(errno)};
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

Expected<frame::Plane<float>> readDepthPng(const std::string& path, double metersPerUnit) {
    auto png = frame::readPng(path);
    if (!png)
        return png.error();
    const cv::Mat& m = *png;
    if (m.type() != CV_16UC1)
        return Error{path + ": expected a 16-bit single-channel depth PNG, found a " + describe(m)};
    frame::Plane<float> depth(m.cols, m.rows);
    for (int y = 0; y < m.rows; ++y) {
        const auto* row = m.ptr<std::uint16_t>(y);
        for (int x = 0; x < m.cols; ++x)
            depth.at(x, y) = row[x] == 0 ? 0.0f : recording::depthFromUnits(row[x], metersPerUnit);
    }
    return depth;
}

Expected<frame::Plane<std::uint8_t>> readConfidencePng(const std::string& path) {
    auto png = frame::readPng(path);
    if (!png)
        return png.error();
    const cv::Mat& m = *png;
    if (m.type() != CV_8UC1)
        return Error{path + ": expected an 8-bit single-channel confidence PNG, found a " + describe(m)};
    frame::Plane<std::uint8_t> confidence(m.cols, m.rows);
    for (int y = 0; y < m.rows; ++y)
        std::memcpy(&confidence.at(0, y), m.ptr<std::uint8_t>(y), static_cast<std::size_t>(m.cols));
    return confidence;
}

Expected<frame::CapturedImage> readColorImage(const std::string& path) {
    auto bytes = base::readFile(path);
    if (!bytes)
        return bytes.error();
    auto image = decodeColor(*bytes);
    if (!image)
        return Error{"cannot read " + path + ": " + image.error().message};
    return image;
}

} // namespace dc::devices::replay
