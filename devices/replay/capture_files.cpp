#include "devices/replay/capture_files.h"

#include "devices/recording/frame_codec.h"
#include "frame/rgb_image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace dc::devices::replay {

namespace {

cv::Mat readImage(const std::string& path, int flags) {
    try {
        return cv::imread(path, flags);
    } catch (const cv::Exception&) {
        return {};
    }
}

std::string describe(const cv::Mat& m) {
    return std::to_string(m.channels()) + "-channel " +
           (m.depth() == CV_16U  ? "16-bit"
            : m.depth() == CV_8U ? "8-bit"
                                 : "non-integer") +
           " image";
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
    const cv::Mat m = readImage(path, cv::IMREAD_UNCHANGED);
    if (m.empty())
        return Error{"cannot read " + path + " (missing or not an image)"};
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
    const cv::Mat m = readImage(path, cv::IMREAD_UNCHANGED);
    if (m.empty())
        return Error{"cannot read " + path + " (missing or not an image)"};
    if (m.type() != CV_8UC1)
        return Error{path + ": expected an 8-bit single-channel confidence PNG, found a " + describe(m)};
    frame::Plane<std::uint8_t> confidence(m.cols, m.rows);
    for (int y = 0; y < m.rows; ++y)
        std::memcpy(&confidence.at(0, y), m.ptr<std::uint8_t>(y), static_cast<std::size_t>(m.cols));
    return confidence;
}

Expected<frame::CapturedImage> readColorImage(const std::string& path) {
    const cv::Mat bgr = readImage(path, cv::IMREAD_COLOR);
    if (bgr.empty())
        return Error{"cannot read " + path + " (missing or not an image)"};
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(bgr.cols) * bgr.rows * 3);
    cv::cvtColor(bgr, cv::Mat(bgr.rows, bgr.cols, CV_8UC3, rgb.data()), cv::COLOR_BGR2RGB);
    return frame::makeRgb24Image(bgr.cols, bgr.rows, std::move(rgb));
}

} // namespace dc::devices::replay
