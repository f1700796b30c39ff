#include "frame/camera_model.h"
#include "frame/frame.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

namespace dc::devices {
namespace {

// A unit quaternion turned into a rotation and back is itself (with w >= 0), for the cases a single
// formula gets wrong: the identity, half-turns (w = 0) about the axes and between them, a nanoradian turn,
// and a turn within 1e-9 of a half-turn.
TEST(QuaternionFromRotation, RoundTripsHalfTurnsAndTheSmallestTurns) {
    const double h = std::sqrt(0.5);
    const double tiny = std::sin(0.5e-9), nearHalf = std::cos(0.5 * (M_PI - 1e-9));
    const std::array<std::array<double, 4>, 9> cases{{{0, 0, 0, 1},
                                                      {1, 0, 0, 0},
                                                      {0, 1, 0, 0},
                                                      {0, 0, 1, 0},
                                                      {h, h, 0, 0},
                                                      {0, -h, h, 0},
                                                      {tiny, 0, 0, std::sqrt(1 - tiny * tiny)},
                                                      {0, std::sqrt(1 - nearHalf * nearHalf), 0, nearHalf},
                                                      {0.5, -0.5, 0.5, 0.5}}};
    for (const auto& q : cases) {
        const std::array<double, 4> back = frame::quaternionFromRotation(frame::rotationFromQuaternion(q));
        // q and -q are one rotation: compare with the one whose w is not negative.
        const double sign =
            q[3] < 0 || (q[3] == 0 && back[0] * q[0] + back[1] * q[1] + back[2] * q[2] < 0) ? -1 : 1;
        for (std::size_t i = 0; i < 4; ++i)
            EXPECT_NEAR(back[i], sign * q[i], 1e-15) << q[0] << " " << q[1] << " " << q[2] << " " << q[3];
        EXPECT_GE(back[3], 0.0);
    }
}

TEST(Intrinsics, ScalingToDepthResolutionScalesEachAxis) {
    const frame::Intrinsics camera{1450.0, 1440.0, 960.0, 720.0, 1920, 1440};
    const frame::Intrinsics depth = camera.scaledTo(256, 192);
    EXPECT_DOUBLE_EQ(depth.fx, 1450.0 * 256.0 / 1920.0);
    EXPECT_DOUBLE_EQ(depth.fy, 1440.0 * 192.0 / 1440.0);
    EXPECT_DOUBLE_EQ(depth.cx, 128.0);
    EXPECT_DOUBLE_EQ(depth.cy, 96.0);
    EXPECT_EQ(depth.width, 256);
    EXPECT_EQ(depth.height, 192);
}

TEST(Intrinsics, RejectsDegenerateValues) {
    EXPECT_TRUE((frame::Intrinsics{500, 500, 320, 240, 640, 480}.valid()));
    EXPECT_FALSE((frame::Intrinsics{0, 500, 320, 240, 640, 480}.valid()));
    EXPECT_FALSE((frame::Intrinsics{-1, 500, 320, 240, 640, 480}.valid()));
    EXPECT_FALSE(
        (frame::Intrinsics{std::numeric_limits<double>::quiet_NaN(), 500, 320, 240, 640, 480}.valid()));
    EXPECT_FALSE(
        (frame::Intrinsics{500, std::numeric_limits<double>::infinity(), 320, 240, 640, 480}.valid()));
    EXPECT_FALSE((frame::Intrinsics{500, 500, 320, 240, 0, 480}.valid()));
}

TEST(Frame, DepthIntrinsicsAreDerivedFromTheImageIntrinsics) {
    frame::Frame frame;
    frame.cameraIntrinsics = {1450.0, 1450.0, 960.0, 720.0, 1920, 1440};
    EXPECT_FALSE(frame.depthIntrinsics().valid()) << "no depth, no depth intrinsics";
    frame.sceneDepth = frame::DepthData{frame::Plane<float>(640, 480), {}};
    const frame::Intrinsics k = frame.depthIntrinsics();
    EXPECT_DOUBLE_EQ(k.fx, 1450.0 / 3.0);
    EXPECT_DOUBLE_EQ(k.cx, 320.0);
    EXPECT_EQ(k.width, 640);
}

TEST(CapturedImage, ByteSizesOfEachFormat) {
    EXPECT_EQ(frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, 4, 2), 8u + 4u);
    EXPECT_EQ(frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, 3, 3),
              9u + 8u); // odd sizes round chroma up
    EXPECT_EQ(frame::CapturedImage::byteSize(frame::PixelFormat::Yuyv, 4, 2), 16u);
    EXPECT_EQ(frame::CapturedImage::byteSize(frame::PixelFormat::Rgb24, 4, 2), 24u);
}

} // namespace
} // namespace dc::devices
