#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <string>

namespace dc::frame {

// Pinhole intrinsics read from a calibration file, at the resolution the file was made for (scale them to a
// stream's size with Intrinsics::scaledTo). Two formats are understood:
//  - OpenCV FileStorage YAML (calibrateCamera's output): image_width, image_height and camera_matrix as an
//    !!opencv-matrix (cameraMatrix and K are accepted as names too);
//  - ROS camera_info YAML (camera_calibration's output): image_width, image_height and camera_matrix as a
//    map with rows, cols and data.
// Distortion is not applied: the cloud unprojects with the pinhole model.
struct Calibration {
    Intrinsics intrinsics;
    std::string format; // "OpenCV YAML" or "ROS camera_info YAML"
};

Expected<Calibration> parseCalibration(const std::string& text, const std::string& origin);
Expected<Calibration> loadCalibration(const std::string& path);

// The stand-in when no calibration is known: square pixels, principal point in the middle, and the
// given horizontal field of view. Geometry built on it is approximate, and the device says so.
Intrinsics intrinsicsFromFieldOfView(int width, int height, double horizontalFovDegrees);

} // namespace dc::frame
