#include "devices/synthetic/synthetic_device.h"
#include "devices/synthetic/synthetic_scene.h"
#include "tests/pose_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace dc::devices {
namespace {

// Analytic ray construction for the fixed camera: independent of the scene's ray caster.
struct AnalyticCamera {
    double ox = 0, oy = scene::kCameraHeight, oz = 0;
    double pitch = scene::kCameraPitchDegrees * std::numbers::pi / 180.0;
    frame::Intrinsics k;

    // World direction of pixel (u, v), scaled so its camera-z component is 1.
    std::array<double, 3> dir(int u, int v) const {
        const double xn = (u - k.cx) / k.fx, yn = (v - k.cy) / k.fy;
        // right = (-1,0,0) (world +x is on the camera's left), down = (0,-cos,-sin), forward = (0,-sin,cos)
        return {-xn, -std::cos(pitch) * yn - std::sin(pitch), -std::sin(pitch) * yn + std::cos(pitch)};
    }
    // Depth at which the ray meets the desk plane y = 0.
    double deskDepth(int u, int v) const { return -oy / dir(u, v)[1]; }
    // Depth at which the ray first meets the apple, or NaN.
    double appleDepth(int u, int v) const {
        const auto d = dir(u, v);
        const double oc[3] = {ox - scene::kAppleCenter[0], oy - scene::kAppleCenter[1],
                              oz - scene::kAppleCenter[2]};
        const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        const double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
        const double c =
            oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - scene::kAppleRadius * scene::kAppleRadius;
        const double disc = b * b - a * c;
        return disc < 0 ? std::nan("") : (-b - std::sqrt(disc)) / a;
    }
};

TEST(SyntheticScene, TrueDepthEqualsTheAnalyticDeskAndApple) {
    const SyntheticScene scene;
    const frame::Intrinsics k = SyntheticScene::cameraIntrinsics().scaledTo(256, 192);
    const frame::Plane<float> depth = scene.trueDepth(k, SyntheticScene::cameraPose(0.0, false));
    const AnalyticCamera cam{.k = k};

    int deskPixels = 0, applePixels = 0;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
            const double apple = cam.appleDepth(u, v);
            if (!std::isnan(apple)) {
                EXPECT_NEAR(depth.at(u, v), apple, 1e-5 * apple) << u << "," << v;
                ++applePixels;
                continue;
            }
            // Bottom rows look at the open desk (nothing else is in front of it there).
            if (v > 170 && u > 100 && u < 160) {
                EXPECT_NEAR(depth.at(u, v), cam.deskDepth(u, v), 1e-5 * cam.deskDepth(u, v)) << u << "," << v;
                ++deskPixels;
            }
        }
    }
    EXPECT_GT(applePixels, 100) << "the apple covers a few hundred depth pixels";
    EXPECT_GT(deskPixels, 500);
}

TEST(SyntheticScene, WindowOpeningHasNoDepthAndLowConfidenceAtItsBorder) {
    const SyntheticScene scene;
    const frame::Intrinsics k = SyntheticScene::cameraIntrinsics().scaledTo(256, 192);
    const frame::Pose pose = SyntheticScene::cameraPose(0.0, false);
    const frame::Plane<float> truth = scene.trueDepth(k, pose);
    const frame::DepthData sensed = scene.sensorDepth(k, pose, 0);
    int holes = 0, borderLow = 0, border = 0;
    for (int v = 1; v < k.height - 1; ++v) {
        for (int u = 1; u < k.width - 1; ++u) {
            if (truth.at(u, v) != 0.0f)
                continue;
            ++holes;
            EXPECT_EQ(sensed.depthMeters.at(u, v), 0.0f) << "no return beyond the window";
            if (truth.at(u + 1, v) > 0.0f) {
                ++border;
                borderLow += sensed.confidence.at(u + 1, v) == 0;
            }
        }
    }
    EXPECT_GT(holes, 200) << "the window looks out beyond the sensor's range";
    EXPECT_GT(border, 10);
    EXPECT_EQ(borderLow, border) << "pixels next to the window's opening are never trusted";
}

TEST(SyntheticScene, NoiseGrowsWithDistanceAndConfidenceFollowsIt) {
    const SyntheticScene scene;
    const frame::Intrinsics k = SyntheticScene::cameraIntrinsics().scaledTo(256, 192);
    const frame::Pose pose = SyntheticScene::cameraPose(0.0, false);
    const frame::Plane<float> truth = scene.trueDepth(k, pose);
    double nearErr = 0, farErr = 0;
    int nearN = 0, farN = 0, nearHigh = 0, farHigh = 0;
    for (std::uint64_t seq = 0; seq < 4; ++seq) {
        const frame::DepthData d = scene.sensorDepth(k, pose, seq);
        for (std::size_t i = 0; i < truth.pixels.size(); ++i) {
            const float t = truth.pixels[i];
            if (t <= 0.0f || d.confidence.pixels[i] == 0)
                continue;
            const double e = std::abs(d.depthMeters.pixels[i] - t);
            if (t < 0.8f) {
                nearErr += e, ++nearN, nearHigh += d.confidence.pixels[i] == 2;
            } else if (t > 1.8f) {
                farErr += e, ++farN, farHigh += d.confidence.pixels[i] == 2;
            }
        }
    }
    ASSERT_GT(nearN, 100);
    ASSERT_GT(farN, 100);
    EXPECT_GT(farErr / farN, 2.0 * nearErr / nearN);
    EXPECT_GT(static_cast<double>(nearHigh) / nearN, 0.5) << "near flat surfaces are mostly high confidence";
    EXPECT_LT(static_cast<double>(farHigh) / farN, 0.1) << "the far wall is not";
}

TEST(SyntheticScene, SensorDepthIsDeterministicPerSeedAndSequence) {
    const frame::Intrinsics k = SyntheticScene::cameraIntrinsics().scaledTo(64, 48);
    const frame::Pose pose = SyntheticScene::cameraPose(0.0, false);
    const SyntheticScene a(7), b(7), c(8);
    EXPECT_EQ(a.sensorDepth(k, pose, 3).depthMeters.pixels, b.sensorDepth(k, pose, 3).depthMeters.pixels);
    EXPECT_NE(a.sensorDepth(k, pose, 3).depthMeters.pixels, a.sensorDepth(k, pose, 4).depthMeters.pixels);
    EXPECT_NE(a.sensorDepth(k, pose, 3).depthMeters.pixels, c.sensorDepth(k, pose, 3).depthMeters.pixels);
}

TEST(SyntheticScene, CameraImageHasEdgesWhereDepthHasEdges) {
    const SyntheticScene scene;
    const frame::Intrinsics k = SyntheticScene::cameraIntrinsics().scaledTo(256, 192);
    const frame::Pose pose = SyntheticScene::cameraPose(0.0, false);
    const frame::CapturedImage image = scene.renderImage(k, pose);
    ASSERT_EQ(image.bytes->size(), frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, 256, 192));
    // Luma across the apple's silhouette differs clearly from the desk beside it.
    const frame::Plane<float> depth = scene.trueDepth(k, pose);
    int strongEdges = 0, edges = 0;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u + 1 < k.width; ++u) {
            const float a = depth.at(u, v), b = depth.at(u + 1, v);
            if (a > 0 && b > 0 && std::abs(a - b) > 0.05f) {
                ++edges;
                const int ya = (*image.bytes)[v * 256 + u], yb = (*image.bytes)[v * 256 + u + 1];
                strongEdges += std::abs(ya - yb) > 8;
            }
        }
    }
    ASSERT_GT(edges, 20);
    EXPECT_GT(static_cast<double>(strongEdges) / edges, 0.5);
}

// The rig's colour sensor inverts its lens once: each pixel's stored direction, put back through the lens,
// lands on that pixel's centre, and the moving rig's images are the scene's renders through that lens.
TEST(SyntheticScene, ALensInvertedOnceLooksWhereEachPixelLooks) {
    const frame::RigCalibration rig = syntheticRigCalibration();
    const frame::CameraModel colour{rig.colour.intrinsics.scaledTo(160, 90), rig.colour.lens};
    ASSERT_NE(colour.lens.model, frame::LensModel::None);
    const LensCamera camera = lensCamera(colour);
    const frame::Intrinsics& k = colour.intrinsics;
    ASSERT_EQ(camera.directions.size(), static_cast<std::size_t>(k.width * k.height));
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u) {
            const auto [x, y] = camera.directions[static_cast<std::size_t>(v * k.width + u)];
            const auto [xd, yd] = frame::distortPoint(colour.lens, x, y);
            ASSERT_NEAR(xd * k.fx + k.cx, u, 1e-6) << u << "," << v;
            ASSERT_NEAR(yd * k.fy + k.cy, v, 1e-6) << u << "," << v;
        }
    SyntheticConfig config;
    config.rig = true;
    config.motion = true;
    config.cameraWidth = 160;
    config.cameraHeight = 90;
    SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    const frame::FramePtr frame = device.makeFrame(0, 1.5);
    ASSERT_TRUE(frame->pose);
    const frame::CapturedImage expected =
        SyntheticScene(config.seed)
            .renderImage(frame::CameraModel{frame->cameraIntrinsics, rig.colour.lens},
                         colourSensorPose(*frame->pose, rig.depthToColour));
    EXPECT_EQ(*frame->capturedImage.bytes, *expected.bytes);
}

TEST(SyntheticDevice, ExactModeDeliversTheGroundTruthWithPose) {
    SyntheticConfig config;
    config.noise = false;
    config.paced = false;
    config.cameraWidth = 320;
    config.cameraHeight = 240;
    SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    ASSERT_TRUE(device.start());
    const CaptureResult r = device.capture(std::chrono::seconds(1));
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame);
    ASSERT_TRUE(r.frame->sceneDepth.has_value());
    ASSERT_TRUE(r.frame->pose.has_value());
    const frame::Plane<float> truth =
        device.scene().trueDepth(r.frame->depthIntrinsics(), SyntheticScene::cameraPose(0.0, false));
    EXPECT_EQ(r.frame->sceneDepth->depthMeters.pixels, truth.pixels);
    EXPECT_EQ(r.frame->capturedImage.width, 320);
    EXPECT_EQ(r.frame->capturedImage.format, frame::PixelFormat::Nv12);
}

TEST(SyntheticScene, PosesAreRotationsEverywhereOnTheSway) {
    for (const bool motion : {false, true})
        for (double t = 0.0; t < 10.0; t += 0.37) // the sway's whole 10 s period
            EXPECT_TRUE(test::isRigid(SyntheticScene::cameraPose(t, motion)))
                << "t = " << t << " motion " << motion;
}

SyntheticConfig smallMovingScene() {
    SyntheticConfig config;
    config.depthWidth = 32;
    config.depthHeight = 24;
    config.cameraWidth = 64;
    config.cameraHeight = 48;
    config.motion = true;
    config.paced = false;
    return config;
}

TEST(SyntheticDevice, FramesRenderedAheadAreDeliveredInOrderAsMakeFrameMakesThem) {
    SyntheticDevice device(smallMovingScene());
    EXPECT_DOUBLE_EQ(device.capabilities().nominalFps, 60.0) << "the rate it promises";
    ASSERT_TRUE(device.open());
    std::int64_t lastTimestampNs = 0;
    for (int run = 0; run < 2; ++run) { // stop and start again: the sequence goes on
        ASSERT_TRUE(device.start());
        for (std::uint64_t i = 0; i < 6; ++i) {
            const CaptureResult r = device.capture(std::chrono::seconds(10));
            ASSERT_EQ(r.kind, CaptureResult::Kind::Frame);
            const std::uint64_t sequence = 6 * static_cast<std::uint64_t>(run) + i;
            EXPECT_EQ(r.frame->sequence, sequence);
            EXPECT_GE(r.frame->timestampNs, lastTimestampNs);
            lastTimestampNs = r.frame->timestampNs;
            const frame::FramePtr expected = device.makeFrame(sequence, static_cast<double>(sequence) / 60.0);
            EXPECT_EQ(r.frame->sceneDepth->depthMeters.pixels, expected->sceneDepth->depthMeters.pixels);
            EXPECT_EQ(*r.frame->capturedImage.bytes, *expected->capturedImage.bytes);
            EXPECT_EQ(r.frame->pose->cameraToWorld, expected->pose->cameraToWorld);
            EXPECT_TRUE(test::isRigid(*r.frame->pose));
        }
        ASSERT_TRUE(device.stop());
    }
}

TEST(SyntheticDevice, MotionMovesThePoseOverTime) {
    const frame::Pose a = SyntheticScene::cameraPose(0.0, true), b = SyntheticScene::cameraPose(2.5, true);
    EXPECT_NE(a.cameraToWorld[12], b.cameraToWorld[12]);
    const frame::Pose still = SyntheticScene::cameraPose(2.5, false);
    EXPECT_EQ(still.cameraToWorld, SyntheticScene::cameraPose(0.0, false).cameraToWorld);
}

} // namespace
} // namespace dc::devices
