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

    std::array<double, 3> apply(const std::array<double, 3>& p) const;
    bool isIdentity() const;
    bool operator==(const RigidTransform&) const = default;
};

// How far R is from a proper rotation: the largest entry of R Rᵀ - I, or infinity when det R <= 0.
double rotationError(const std::array<double, 9>& rotation);

// The ideal normalised point where the lens images it, and back.
std::array<double, 2> distortPoint(const Lens& lens, double x, double y);
std::array<double, 2> undistortPoint(const Lens& lens, double x, double y);

// Pixel of a point in the camera's frame (distortion applied); none behind or on the camera's plane.
// Pixel centres are at integer coordinates, as Intrinsics places them.
std::optional<std::array<double, 2>> projectPoint(const CameraModel& camera, const std::array<double, 3>& p);
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
