#pragma once

#include "frame/frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace dc::test {

inline constexpr double kDegToRad = std::numbers::pi / 180.0;

// Whether a camera-to-world pose is rigid: its rotation part orthonormal (R^T R = I) with determinant +1,
// not a reflection, and its bottom row (0, 0, 0, 1). Every source that gives poses must pass this.
inline testing::AssertionResult isRigid(const frame::Pose& pose, double tolerance = 1e-9) {
    const auto r = [&](int row, int col) { return pose.cameraToWorld[col * 4 + row]; };
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double dot = 0.0;
            for (int k = 0; k < 3; ++k)
                dot += r(k, i) * r(k, j);
            if (std::abs(dot - (i == j ? 1.0 : 0.0)) > tolerance)
                return testing::AssertionFailure() << "columns " << i << " and " << j << " have dot product "
                                                   << dot << ": not orthonormal";
        }
    const double det = r(0, 0) * (r(1, 1) * r(2, 2) - r(1, 2) * r(2, 1)) -
                       r(0, 1) * (r(1, 0) * r(2, 2) - r(1, 2) * r(2, 0)) +
                       r(0, 2) * (r(1, 0) * r(2, 1) - r(1, 1) * r(2, 0));
    if (std::abs(det - 1.0) > tolerance)
        return testing::AssertionFailure() << "determinant " << det << (det < 0 ? ": a reflection" : "");
    if (r(3, 0) != 0.0 || r(3, 1) != 0.0 || r(3, 2) != 0.0 || r(3, 3) != 1.0)
        return testing::AssertionFailure() << "bottom row is not (0, 0, 0, 1)";
    return testing::AssertionSuccess();
}

} // namespace dc::test
