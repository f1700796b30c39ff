#include "frame/camera_pose.h"

#include "base/files.h"
#include "frame/calibration_fields.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dc::frame {

Expected<RigidTransform> poseFromQuaternion(const std::array<double, 7>& values) {
    if (!std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }))
        return Error{"not a finite number"};
    const double norm = std::hypot(std::hypot(values[3], values[4]), std::hypot(values[5], values[6]));
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
        char text[96];
        std::snprintf(text, sizeof text, "the quaternion's norm is %.6g, not 1 (within %g)", norm,
                      kQuaternionNormTolerance);
        return Error{text};
    }
    return rigidFromQuaternion({values[0], values[1], values[2]},
                               {values[3] / norm, values[4] / norm, values[5] / norm, values[6] / norm});
}

Expected<RigidTransform> loadPoseFile(const std::string& path) {
    auto bytes = base::readFile(path);
    if (!bytes)
        return bytes.error();
    const auto root = fields::parseDocument(std::string(bytes->begin(), bytes->end()), path);
    if (!root)
        return root.error();
    auto numbers = fields::numbers(fields::child(*root, "pose"), "pose", path, 7);
    if (!numbers)
        return numbers.error();
    std::array<double, 7> values{};
    std::copy_n(numbers->begin(), 7, values.begin());
    auto pose = poseFromQuaternion(values);
    if (!pose)
        return fields::fieldError(path, "pose", pose.error().message);
    return pose;
}

} // namespace dc::frame
