#include "frame/camera_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dc::frame {

// Fixed-point iteration, as OpenCV's undistortPoints does: it converges for the monotonic distortions of
// real lenses, and 20 steps bring it well below 1e-6 of a normalised unit (a thousandth of a pixel) for the
// strongest lenses we read.
std::array<double, 2> invertBrownConrady(const std::array<double, 5>& c, double xd, double yd) {
    double x = xd, y = yd;
    for (int i = 0; i < 20; ++i) {
        const double r2 = x * x + y * y;
        const double radial = 1.0 + r2 * (c[0] + r2 * (c[1] + r2 * c[4]));
        const double dx = 2.0 * c[2] * x * y + c[3] * (r2 + 2.0 * x * x);
        const double dy = c[2] * (r2 + 2.0 * y * y) + 2.0 * c[3] * x * y;
        x = (xd - dx) / radial;
        y = (yd - dy) / radial;
    }
    return {x, y};
}

const char* toString(LensModel model) {
    switch (model) {
    case LensModel::None:
        return "none";
    case LensModel::BrownConrady:
        return "brown_conrady";
    case LensModel::InverseBrownConrady:
        return "inverse_brown_conrady";
    }
    return "unknown";
}

bool RigidTransform::isIdentity() const {
    return *this == RigidTransform{};
}

RigidTransform compose(const RigidTransform& second, const RigidTransform& first) {
    RigidTransform out;
    const auto& a = second.rotation;
    const auto& b = first.rotation;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            out.rotation[r * 3 + c] = a[r * 3] * b[c] + a[r * 3 + 1] * b[3 + c] + a[r * 3 + 2] * b[6 + c];
    out.translationMeters = second.apply(first.translationMeters);
    return out;
}

RigidTransform inverse(const RigidTransform& t) {
    RigidTransform out;
    const auto& r = t.rotation;
    out.rotation = {r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
    const std::array<double, 3> moved = out.apply(t.translationMeters);
    out.translationMeters = {-moved[0], -moved[1], -moved[2]};
    return out;
}

RigidTransform rigidFromPose(const Pose& pose) {
    const auto& m = pose.cameraToWorld;
    return {{m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]}, {m[12], m[13], m[14]}};
}

Pose poseFromRigid(const RigidTransform& t) {
    const auto& r = t.rotation;
    const auto& p = t.translationMeters;
    return {{r[0], r[3], r[6], 0.0, r[1], r[4], r[7], 0.0, r[2], r[5], r[8], 0.0, p[0], p[1], p[2], 1.0}};
}

std::array<double, 9> rotationFromQuaternion(const std::array<double, 4>& xyzw) {
    const auto [x, y, z, w] = xyzw;
    return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
            2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
            2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
}

std::array<double, 4> quaternionFromRotation(const std::array<double, 9>& r) {
    // 4x², 4y², 4z², 4w² from the trace and the diagonal; the largest is far from 0, so dividing by it is
    // safe.
    const std::array<double, 4> four{1 + r[0] - r[4] - r[8], 1 - r[0] + r[4] - r[8], 1 - r[0] - r[4] + r[8],
                                     1 + r[0] + r[4] + r[8]};
    const auto largest = static_cast<std::size_t>(std::max_element(four.begin(), four.end()) - four.begin());
    const double s = 2.0 * std::sqrt(std::max(four[largest], 0.0)); // 4 times that component
    std::array<double, 4> q{};
    switch (largest) {
    case 0:
        q = {s / 4, (r[1] + r[3]) / s, (r[2] + r[6]) / s, (r[7] - r[5]) / s};
        break;
    case 1:
        q = {(r[1] + r[3]) / s, s / 4, (r[5] + r[7]) / s, (r[2] - r[6]) / s};
        break;
    case 2:
        q = {(r[2] + r[6]) / s, (r[5] + r[7]) / s, s / 4, (r[3] - r[1]) / s};
        break;
    default:
        q = {(r[7] - r[5]) / s, (r[2] - r[6]) / s, (r[3] - r[1]) / s, s / 4};
        break;
    }
    if (q[3] < 0.0)
        for (double& v : q)
            v = -v;
    return q;
}

RigidTransform rigidFromQuaternion(const std::array<double, 3>& translationMeters,
                                   const std::array<double, 4>& xyzw) {
    return {rotationFromQuaternion(xyzw), translationMeters};
}

double rotationError(const std::array<double, 9>& r) {
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (!(det > 0.0))
        return std::numeric_limits<double>::infinity();
    double worst = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double dotIJ =
                r[3 * i] * r[3 * j] + r[3 * i + 1] * r[3 * j + 1] + r[3 * i + 2] * r[3 * j + 2];
            worst = std::max(worst, std::abs(dotIJ - (i == j ? 1.0 : 0.0)));
        }
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
}

std::array<double, 2> undistortPoint(const Lens& lens, double x, double y) {
    switch (lens.model) {
    case LensModel::None:
        return {x, y};
    case LensModel::BrownConrady:
        return invertBrownConrady(lens.coefficients, x, y);
    case LensModel::InverseBrownConrady:
        return brownConrady(lens.coefficients, x, y);
    }
    return {x, y};
}

std::array<double, 3> pixelRay(const CameraModel& camera, double u, double v) {
    const Intrinsics& k = camera.intrinsics;
    const auto [x, y] = undistortPoint(camera.lens, (u - k.cx) / k.fx, (v - k.cy) / k.fy);
    return {x, y, 1.0};
}

std::string describe(const RigCalibration& rig) {
    return "two sensors, calibration " + rig.name + (rig.approximate ? " (approximate)" : "");
}

} // namespace dc::frame
