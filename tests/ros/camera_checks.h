#pragma once

#include "devices/recording/frame_codec.h"
#include "frame/frame.h"
#include "tests/ros/camera_pattern.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>

// Checks of a frame against the test cameras' formulas (camera_pattern.h), pixel for pixel.
namespace dc::test::camera {

// The depth of frame `i` at `width` x `height`: millimetres decoded as depthcloud decodes 16UC1, or, when
// the camera sent 32FC1, the float meters it sent.
inline void expectDepth(const frame::Frame& f, std::int64_t i, int width, int height, bool meters) {
    ASSERT_TRUE(f.sceneDepth);
    const auto& d = f.sceneDepth->depthMeters;
    ASSERT_EQ(d.width, width);
    ASSERT_EQ(d.height, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::uint16_t units = depthUnits(x, y, i);
            const float expected = meters ? static_cast<float>(units) * 0.001f
                                          : devices::recording::depthFromUnits(units, 0.001);
            ASSERT_EQ(d.at(x, y), expected) << "frame " << i << " at " << x << "," << y;
        }
}

inline void expectColor(const frame::Frame& f, std::int64_t i, int width, int height) {
    ASSERT_EQ(f.capturedImage.format, frame::PixelFormat::Rgb24);
    ASSERT_EQ(f.capturedImage.width, width);
    ASSERT_EQ(f.capturedImage.height, height);
    const auto& bytes = *f.capturedImage.bytes;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const auto rgb = colorRgb(x, y, i);
            const std::size_t at = 3 * (static_cast<std::size_t>(y) * width + x);
            ASSERT_EQ(bytes[at], rgb[0]) << "frame " << i << " at " << x << "," << y;
            ASSERT_EQ(bytes[at + 1], rgb[1]) << "frame " << i << " at " << x << "," << y;
            ASSERT_EQ(bytes[at + 2], rgb[2]) << "frame " << i << " at " << x << "," << y;
        }
}

// The lens camera_pattern.h gives at 64x48, scaled to the depth image's size.
inline void expectIntrinsics(const frame::Frame& f, int width, int height) {
    const frame::Intrinsics k = f.depthIntrinsics();
    const double sx = width / 64.0, sy = height / 48.0;
    EXPECT_EQ(k.width, width);
    EXPECT_EQ(k.height, height);
    EXPECT_NEAR(k.fx, kFx * sx, 1e-9);
    EXPECT_NEAR(k.fy, kFy * sy, 1e-9);
    EXPECT_NEAR(k.cx, kCx * sx, 1e-9);
    EXPECT_NEAR(k.cy, kCy * sy, 1e-9);
}

} // namespace dc::test::camera
