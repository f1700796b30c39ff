#pragma once

#include "frame/frame.h"

#include <array>
#include <optional>
#include <string>

namespace dc::frame {

// How a lens bends rays, in normalised image coordinates (x = X/Z, y = Y/Z).
//  - BrownConrady: OpenCV's (and RealSense's "modified") model. The coefficients take the ideal pinhole
//    point to where the lens images it, so projecting applies them and unprojecting inverts them.
//  - InverseBrownConrady: the same polynomial the other way round, as some depth cameras report it: the
//    coefficients take the imaged point back to the ideal one, so unprojecting is the direct evaluation.
enum class LensModel { None, BrownConrady, InverseBrownConrady };

const char* toString(LensModel model);

struct Lens {
    LensModel model = LensModel::None;
    std::array<double, 5> coefficients{}; // k1 k2 p1 p2 k3, OpenCV's order

    bool operator==(const Lens&) const = default;
};

// A camera: pinhole intrinsics at its calibrated resolution, and its lens.
struct CameraModel {
    Intrinsics intrinsics;
    Lens lens;

    bool operator==(const CameraModel&) const = default;
};

// p' = R p + t: a point in one camera's frame (OpenCV axes, meters) into another's.
struct RigidTransform {
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1}; // row-major
    std::array<double, 3> translationMeters{};

    std::array<double, 3> apply(const std::array<double, 3>& p) const {
        const auto& r = rotation;
        const auto& t = translationMeters;
        return {r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + t[0],
                r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + t[1],
                r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + t[2]};
    }
    bool isIdentity() const;
    bool operator==(const RigidTransform&) const = default;
};

// The algebra of rigid transforms, the one copy every layer uses.
// `first`, then `second`: compose(second, first).apply(p) == second.apply(first.apply(p)).
RigidTransform compose(const RigidTransform& second, const RigidTransform& first);
// The transform back: Rᵀ and -Rᵀ t.
RigidTransform inverse(const RigidTransform& t);
// The row-major rotation of the quaternion (x, y, z, w), which must already be a unit one: it is used as it
// is, not normalised.
std::array<double, 9> rotationFromQuaternion(const std::array<double, 4>& xyzw);
// The unit quaternion (x, y, z, w) of a rotation, w >= 0. Computed from the largest of its four squared
// components (Shepperd's choice), so that half-turns, whose w is 0, keep their full precision.
std::array<double, 4> quaternionFromRotation(const std::array<double, 9>& rotation);
// A translation in meters and a unit quaternion (x, y, z, w), as ROS's and TUM's poses give them.
RigidTransform rigidFromQuaternion(const std::array<double, 3>& translationMeters,
                                   const std::array<double, 4>& xyzw);

// A frame's pose (column-major 4x4) as the rigid transform camera -> world, and back.
RigidTransform rigidFromPose(const Pose& pose);
Pose poseFromRigid(const RigidTransform& cameraToWorld);

// How far R is from a proper rotation: the largest entry of R Rᵀ - I, or infinity when det R <= 0.
double rotationError(const std::array<double, 9>& rotation);

// The Brown–Conrady polynomial: radial terms k1 k2 k3 and tangential terms p1 p2 (inline: registration
// evaluates it for every depth sample).
inline std::array<double, 2> brownConrady(const std::array<double, 5>& c, double x, double y) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (c[0] + r2 * (c[1] + r2 * c[4]));
    return {x * radial + 2.0 * c[2] * x * y + c[3] * (r2 + 2.0 * x * x),
            y * radial + c[2] * (r2 + 2.0 * y * y) + 2.0 * c[3] * x * y};
}
// The point that the polynomial takes to (x, y).
std::array<double, 2> invertBrownConrady(const std::array<double, 5>& c, double x, double y);

// The ideal normalised point where the lens images it, and back.
inline std::array<double, 2> distortPoint(const Lens& lens, double x, double y) {
    switch (lens.model) {
    case LensModel::None:
        return {x, y};
    case LensModel::BrownConrady:
        return brownConrady(lens.coefficients, x, y);
    case LensModel::InverseBrownConrady:
        return invertBrownConrady(lens.coefficients, x, y);
    }
    return {x, y};
}
std::array<double, 2> undistortPoint(const Lens& lens, double x, double y);

// Pixel of a point in the camera's frame (distortion applied); none behind or on the camera's plane.
// Pixel centres are at integer coordinates, as Intrinsics places them.
inline std::optional<std::array<double, 2>> projectPoint(const CameraModel& camera,
                                                         const std::array<double, 3>& p) {
    if (!(p[2] > 0.0))
        return std::nullopt;
    const auto [x, y] = distortPoint(camera.lens, p[0] / p[2], p[1] / p[2]);
    const Intrinsics& k = camera.intrinsics;
    return std::array<double, 2>{k.fx * x + k.cx, k.fy * y + k.cy};
}
// The ray through pixel (u, v), scaled to z = 1 (distortion removed).
std::array<double, 3> pixelRay(const CameraModel& camera, double u, double v);

// The calibration of a camera whose depth and colour come from two sensors: each sensor's model, and the
// rigid transform from the depth sensor's frame to the colour sensor's. Intrinsics are at the resolution
// the calibration was made for; scale them to a stream's size with Intrinsics::scaledTo.
struct RigCalibration {
    CameraModel depth;
    CameraModel colour;
    RigidTransform depthToColour;
    std::string name;         // what the status line calls it (a file, "synthetic rig")
    bool approximate = false; // not measured on this very camera (a default or a nominal value)
};

// What the status line says about it: "two sensors, calibration NAME", "(approximate)" when it is.
std::string describe(const RigCalibration& rig);

} // namespace dc::frame
