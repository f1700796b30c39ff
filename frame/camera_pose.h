#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"

#include <array>
#include <string>

// A camera's place in the world: its camera-to-world transform (p_world = R p_camera + t), given as a
// position and an orientation quaternion, as ROS's geometry_msgs/Pose and TUM's trajectories give it.
namespace dc::frame {

// A quaternion whose norm is farther than this from 1 is not a typo's rounding but a wrong value (or the
// wrong order of its parts), so it is refused rather than silently normalised.
inline constexpr double kQuaternionNormTolerance = 1e-3;

// x, y, z in meters, then qx, qy, qz, qw: the transform, the quaternion normalised. An error says what is
// wrong with the values (not finite, or the quaternion's norm) and names no field: callers add it.
Expected<RigidTransform> poseFromQuaternion(const std::array<double, 7>& values);

// A pose file: YAML or JSON whose `pose` holds the seven numbers of poseFromQuaternion, e.g.
// `pose: [0.1, 0, 1.2, 0, 0, 0, 1]` or `{"pose": [0.1, 0, 1.2, 0, 0, 0, 1]}`. Errors name the file.
Expected<RigidTransform> loadPoseFile(const std::string& path);

} // namespace dc::frame
