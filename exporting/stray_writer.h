#pragma once

#include "base/expected.h"
#include "devices/video/video_codec.h"
#include "frame/frame.h"
#include "frame/jpeg_codec.h"

#include <opencv2/core.hpp>

#include <memory>
#include <string>

namespace dc::exporting {

// Writes 16-bit millimetre depth (0 = no measurement, clamped at 65.535 m) as a PNG, atomically.
Status writeDepthPng16(const std::string& path, const frame::Plane<float>& depthMeters);

// Writes frames in the Stray Scanner layout: depth/ and confidence/ PNGs numbered from 0, rgb.mp4,
// camera_matrix.csv (intrinsics of the video) and odometry.csv (camera-to-world per frame).
class StrayWriter {
public:
    // `fps`: the video's frame rate (the capture's mean rate).
    StrayWriter(std::string directory, double fps) : dir_(std::move(directory)), fps_(fps) {}

    Status add(const frame::Frame& frame);
    // Closes the video and writes the CSV files; the directory is complete only after this.
    Status finish();

private:
    Status addColor(const frame::Frame& frame);

    std::string dir_;
    double fps_;
    std::size_t count_ = 0;
    bool withConfidence_ = false; // decided by the first frame, so every frame has the same files
    frame::Intrinsics intrinsics_;
    std::string odometry_ = "timestamp, frame, x, y, z, qx, qy, qz, qw, fx, fy, cx, cy\n";
    std::unique_ptr<devices::video::VideoWriter> video_;
    frame::JpegDecoder jpegDecoder_;
    cv::Size videoSize_;
};

} // namespace dc::exporting
