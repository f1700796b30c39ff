#pragma once

#include "devices/replay/replay_source.h"

namespace dc::devices::replay {

// A depthcloud recording (docs/recording-format.md).
Expected<std::unique_ptr<ReplaySource>> openRecordingSource(const std::string& path);

// A Stray Scanner directory: depth/NNNNNN.png (uint16 mm), confidence/NNNNNN.png (0/1/2, optional),
// rgb.mp4, camera_matrix.csv (intrinsics of the video), odometry.csv (camera-to-world per frame).
Expected<std::unique_ptr<ReplaySource>> openStraySource(const std::string& directory);

struct TumOptions {
    double maxTimeDifferenceSeconds = 0.02; // TUM's associate.py default
};
// A TUM RGB-D directory: rgb.txt and depth.txt (timestamped file lists), optional groundtruth.txt.
Expected<std::unique_ptr<ReplaySource>> openTumSource(const std::string& directory, TumOptions options = {});

// Replaces every frame's camera intrinsics with a calibration file's (devices/calibration.h: OpenCV or
// ROS YAML), scaled from the calibration's image size to the camera image's.
Expected<std::unique_ptr<ReplaySource>> withCalibration(std::unique_ptr<ReplaySource> source,
                                                        const std::string& calibrationPath);

} // namespace dc::devices::replay
