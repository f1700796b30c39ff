#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"
#include "frame/frame.h"

#include <optional>
#include <string>

namespace dc::frame {

// A calibration read from a file, at the resolution the file was made for (scale it to a stream's size
// with Intrinsics::scaledTo). One camera:
//  - OpenCV FileStorage YAML (calibrateCamera's output): image_width, image_height and camera_matrix as an
//    !!opencv-matrix (cameraMatrix and K are accepted as names too);
//  - ROS camera_info YAML (camera_calibration's output): image_width, image_height and camera_matrix as a
//    map with rows, cols and data.
// Its distortion is not applied: the cloud unprojects with the pinhole model.
// Two sensors, depth first and colour second (`rig` is set):
//  - OpenCV FileStorage YAML or JSON as cv::stereoCalibrate's users write it: K1 D1 K2 D2 R T (M1, M2 and
//    cameraMatrix1/2, distCoeffs1/2 accepted too), image_size1 and image_size2 as [width, height], T in
//    meters, optional lens_model1/2 (none, brown_conrady, inverse_brown_conrady; default brown_conrady);
//  - Kalibr's camchain.yaml: cam0 (depth) and cam1 (colour), each pinhole with intrinsics [fu, fv, pu, pv],
//    distortion_model radtan or none, distortion_coeffs and resolution; cam1.T_cn_cnm1 takes cam0's points
//    to cam1's.
struct Calibration {
    Intrinsics intrinsics;             // the camera image's (the colour sensor's for two sensors)
    std::string format;                // e.g. "OpenCV YAML", "Kalibr camchain"
    std::optional<RigCalibration> rig; // two-sensor files only
    // The fields that give each sensor's image size, named when a stream does not fit them.
    std::string depthSizeField;
    std::string colourSizeField;
};

Expected<Calibration> parseCalibration(const std::string& text, const std::string& origin);
Expected<Calibration> loadCalibration(const std::string& path);

enum class CalibrationFormat {
    OpenCvYaml,
    RosCameraInfo,
    OpenCvStereoYaml,
    OpenCvStereoJson,
    KalibrCamchain
};

// The calibration in one of the formats above, as parseCalibration reads it back. A two-sensor format
// needs `rig`; Kalibr has no k3 and no inverse lens, and refuses a calibration that uses them.
Expected<std::string> writeCalibration(const Calibration& calibration, CalibrationFormat format);

// Whether the streams fit a two-sensor calibration: each image the size its sensor was calibrated at, or
// that size scaled evenly (the same shape). The error names the calibration's field.
Status checkStreamSizes(const Calibration& calibration, int depthWidth, int depthHeight, int colourWidth,
                        int colourHeight);

// The stand-in when no calibration is known: square pixels, principal point in the middle, and the
// given horizontal field of view. Geometry built on it is approximate, and the device says so.
Intrinsics intrinsicsFromFieldOfView(int width, int height, double horizontalFovDegrees);

} // namespace dc::frame
