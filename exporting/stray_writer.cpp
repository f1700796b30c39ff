#include "exporting/stray_writer.h"

#include "base/files.h"

#include "frame/png_codec.h"
#include "frame/rgb_image.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace dc::exporting {

namespace {

std::string numbered(std::size_t i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    return name;
}

// The fastest zlib level: an export writes two PNGs a frame, and depth maps compress well at any level.
constexpr int kPngCompression = 1;

// Unit quaternion (x, y, z, w) of the rotation part of a column-major camera-to-world matrix.
std::array<double, 4> quaternionOf(const frame::Pose& pose) {
    const auto m = [&](int row, int col) { return pose.cameraToWorld[col * 4 + row]; };
    const double trace = m(0, 0) + m(1, 1) + m(2, 2);
    std::array<double, 4> q{};
    // Shepperd's method: divide by the largest of the four candidates for numerical stability.
    if (trace > 0.0) {
        const double s = 2.0 * std::sqrt(1.0 + trace);
        q = {(m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s, 0.25 * s};
    } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
        const double s = 2.0 * std::sqrt(1.0 + m(0, 0) - m(1, 1) - m(2, 2));
        q = {0.25 * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s, (m(2, 1) - m(1, 2)) / s};
    } else if (m(1, 1) > m(2, 2)) {
        const double s = 2.0 * std::sqrt(1.0 + m(1, 1) - m(0, 0) - m(2, 2));
        q = {(m(0, 1) + m(1, 0)) / s, 0.25 * s, (m(1, 2) + m(2, 1)) / s, (m(0, 2) - m(2, 0)) / s};
    } else {
        const double s = 2.0 * std::sqrt(1.0 + m(2, 2) - m(0, 0) - m(1, 1));
        q = {(m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25 * s, (m(1, 0) - m(0, 1)) / s};
    }
    return q;
}

} // namespace

Status writeDepthPng16(const std::string& path, const frame::Plane<float>& depthMeters) {
    cv::Mat mm(depthMeters.height, depthMeters.width, CV_16UC1);
    for (int y = 0; y < depthMeters.height; ++y) {
        auto* row = mm.ptr<std::uint16_t>(y);
        for (int x = 0; x < depthMeters.width; ++x) {
            const float m = depthMeters.at(x, y);
            row[x] = std::isfinite(m) && m > 0.0f
                         ? static_cast<std::uint16_t>(std::clamp(std::lround(m * 1000.0), 0L, 65535L))
                         : 0;
        }
    }
    return frame::writePng(path, mm, kPngCompression);
}

Status StrayWriter::add(const frame::Frame& frame) {
    if (!frame.sceneDepth)
        return Error{"frame " + std::to_string(frame.sequence) + " has no depth"};
    if (count_ == 0) {
        // confidence/ only when there is confidence: an empty folder would read as a count mismatch.
        std::error_code ec;
        withConfidence_ = !frame.sceneDepth->confidence.empty();
        for (const char* sub : {"depth", "confidence"}) {
            if (std::string(sub) == "confidence" && !withConfidence_)
                continue;
            if (std::filesystem::create_directories(std::filesystem::path(dir_) / sub, ec); ec)
                return Error{"cannot create " + dir_ + "/" + sub + ": " + ec.message()};
        }
        intrinsics_ = frame.cameraIntrinsics;
    }
    const std::string name = numbered(count_);
    if (Status s = writeDepthPng16(dir_ + "/depth/" + name, frame.sceneDepth->depthMeters); !s)
        return s;
    if (withConfidence_) {
        const auto& depth = frame.sceneDepth->depthMeters;
        const auto& confidence = frame.sceneDepth->confidence;
        cv::Mat c(depth.height, depth.width, CV_8UC1, cv::Scalar(0)); // a frame without any: all low
        if (confidence.width == depth.width && confidence.height == depth.height && !confidence.empty())
            c = cv::Mat(depth.height, depth.width, CV_8UC1,
                        const_cast<std::uint8_t*>(confidence.pixels.data()));
        if (Status s = frame::writePng(dir_ + "/confidence/" + name, c, kPngCompression); !s)
            return s;
    }
    if (Status s = addColor(frame); !s)
        return s;
    const frame::Pose pose = frame.pose.value_or(frame::Pose{});
    const auto q = quaternionOf(pose);
    char row[512];
    std::snprintf(row, sizeof(row),
                  "%.9f, %06zu, %.9f, %.9f, %.9f, %.9f, %.9f, %.9f, %.9f, %.6f, %.6f, %.6f, %.6f\n",
                  static_cast<double>(frame.timestampNs) * 1e-9, count_, pose.cameraToWorld[12],
                  pose.cameraToWorld[13], pose.cameraToWorld[14], q[0], q[1], q[2], q[3], intrinsics_.fx,
                  intrinsics_.fy, intrinsics_.cx, intrinsics_.cy);
    odometry_ += row;
    ++count_;
    return {};
}

Status StrayWriter::addColor(const frame::Frame& frame) {
    if (frame.capturedImage.empty())
        return {};
    auto decoded = jpegDecoder_.decode(frame.capturedImage); // a camera's MJPEG; other formats as they are
    if (!decoded)
        return Error{"cannot export the camera image: " + decoded.error().message};
    const frame::CapturedImage& image = *decoded;
    std::vector<std::uint8_t> rgb = frame::toRgb24(image);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(image.height, image.width, CV_8UC3, rgb.data()), bgr, cv::COLOR_RGB2BGR);
    if (!video_) {
        if (Status s = devices::video::loadVideoSupport(); !s)
            return s;
        videoSize_ = bgr.size();
        // The container is chosen by extension, so the temporary name keeps ".mp4".
        const std::string tmp = dir_ + "/rgb.partial.mp4";
        auto writer = devices::video::openVideoWriter(tmp, {"avc1", "mp4v"}, fps_, videoSize_);
        if (!writer)
            return Error{"cannot create " + tmp + " (no H.264 or MPEG-4 encoder)"};
        video_ = std::move(*writer);
    }
    if (bgr.size() != videoSize_)
        cv::resize(bgr, bgr, videoSize_);
    video_->write(bgr);
    return {};
}

Status StrayWriter::finish() {
    if (count_ == 0)
        return Error{"no frames to write to " + dir_};
    if (video_) {
        video_->close();
        video_.reset();
        std::error_code ec;
        std::filesystem::rename(dir_ + "/rgb.partial.mp4", dir_ + "/rgb.mp4", ec);
        if (ec)
            return Error{"cannot rename " + dir_ + "/rgb.partial.mp4: " + ec.message()};
    }
    char matrix[256];
    std::snprintf(matrix, sizeof(matrix), "%.17g,0.0,%.17g\n0.0,%.17g,%.17g\n0.0,0.0,1.0\n", intrinsics_.fx,
                  intrinsics_.cx, intrinsics_.fy, intrinsics_.cy);
    if (Status s = base::writeTextFile(dir_ + "/camera_matrix.csv", matrix); !s)
        return s;
    return base::writeTextFile(dir_ + "/odometry.csv", odometry_);
}

} // namespace dc::exporting
