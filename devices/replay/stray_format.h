#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <string>
#include <string_view>
#include <vector>

// The text files of a Stray Scanner capture, parsed without touching the disk (the fuzz targets call
// these directly).
namespace dc::devices::replay {

// camera_matrix.csv: three rows of three numbers, the intrinsics of the video frames. The returned
// intrinsics have no size: the video provides it.
Expected<frame::Intrinsics> parseStrayCameraMatrix(std::string_view text, const std::string& file);

struct StrayOdometryRow {
    double timestampSeconds = 0.0;
    frame::Pose pose; // camera-to-world, OpenCV camera axes
};

// odometry.csv: an optional header line, then "timestamp, frame, x, y, z, qx, qy, qz, qw[, ...]" per
// frame, in frame order.
Expected<std::vector<StrayOdometryRow>> parseStrayOdometry(std::string_view text, const std::string& file);

} // namespace dc::devices::replay
