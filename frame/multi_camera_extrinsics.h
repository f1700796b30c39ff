#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"

#include <string>
#include <vector>

namespace dc::frame {

// One camera of a rig and where it sits: p_world = R p_camera + t.
struct CameraExtrinsics {
    std::string name; // as its file names it: "cam1" (Kalibr), "camera_1" (OpenCV)
    RigidTransform cameraToWorld;

    bool operator==(const CameraExtrinsics&) const = default;
};

// Several cameras' extrinsics, in the file's order. Two formats, both read and written:
//  - Kalibr's camchain.yaml with N cameras cam0..camN-1: each camK (K >= 1) holds T_cn_cnm1, the 4x4
//    transform from cam(K-1)'s frame to camK's. The world is cam0's frame, so cam0 is the identity (the
//    one camera the format places without a transform); the other fields (intrinsics...) are not read
//    here. Written with T_cn_cnm1 only, so the first camera must be the world's frame (the identity).
//  - OpenCV FileStorage YAML (or JSON): `camera_count: N` and camera_0..camera_<N-1>, each a 4x4
//    !!opencv-matrix taking that camera's points to the world's (camera-to-world, row-major).
// Written files are named by position (camK, camera_K) whatever the cameras' names, and read back equal to
// within the printed digits (17: exactly).
struct CameraExtrinsicsSet {
    std::vector<CameraExtrinsics> cameras;
    std::string format; // "Kalibr camchain" or "OpenCV extrinsics"

    // The camera called `name`; none when no camera is.
    const CameraExtrinsics* find(const std::string& name) const;
};

// Errors are one line naming the file, the camera and its field ("cam2.T_cn_cnm1: missing").
Expected<CameraExtrinsicsSet> parseCameraExtrinsics(const std::string& text, const std::string& origin);
Expected<CameraExtrinsicsSet> loadCameraExtrinsics(const std::string& path);

enum class ExtrinsicsFormat { KalibrCamchain, OpenCvYaml };

Expected<std::string> writeCameraExtrinsics(const CameraExtrinsicsSet& set, ExtrinsicsFormat format);

} // namespace dc::frame
