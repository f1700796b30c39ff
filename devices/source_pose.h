#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"

#include <optional>
#include <string>

namespace dc::devices {

// Where a source sits in the world, from its spec's pose= option, whatever the source's kind:
//  - pose=X,Y,Z,QX,QY,QZ,QW: the camera's position in meters and its orientation as a unit quaternion
//    (ROS's order, w last; normalised, refused when its norm is not within 1e-3 of 1);
//  - pose=FILE: the same seven numbers in a YAML or JSON file as `pose: [X, Y, Z, QX, QY, QZ, QW]`
//    (frame::loadPoseFile);
//  - pose=FILE#CAMERA: camera CAMERA (cam1, camera_1...) of a rig's extrinsics file, a Kalibr camchain or
//    OpenCV extrinsics (frame::loadCameraExtrinsics), in that file's world.
// FILE may not contain ':', which separates the spec's options.
// The kinds' own parsers never see pose=: openSourceSpec opens `spec` and places the device it made with
// the transform (Device::place).
struct SourcePlacement {
    std::string spec; // the spec without its pose= option, every other character as given
    std::optional<frame::RigidTransform> cameraToWorld; // none when the spec gives no pose
};

// An error is one line naming pose= and what is wrong (the count, a number, the quaternion, the file).
Expected<SourcePlacement> sourcePlacement(const std::string& spec);
// A pose= value alone (seven numbers, FILE or FILE#CAMERA); the error says what is wrong, not where.
Expected<frame::RigidTransform> parsePoseValue(const std::string& value);

} // namespace dc::devices
