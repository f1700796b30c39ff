#include "devices/source_spec.h"
#include "devices/synthetic/synthetic_device.h"
#include "devices/synthetic/synthetic_scene.h"
#include "frame/camera_model.h"
#include "processing/point_cloud.h"
#include "processing/registration.h"
#include "tests/small_rig.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dc::processing {
namespace {

using devices::SyntheticScene;

double percentile(std::vector<double> values, double fraction) {
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1))];
}

struct RigScene {
    frame::RigCalibration rig = devices::syntheticRigCalibration();
    SyntheticScene scene;
    frame::Pose pose = SyntheticScene::cameraPose(0.0, false);
    frame::Plane<float> depth = scene.trueDepth(rig.depth.intrinsics, pose);
    devices::RegistrationTruth truth =
        scene.registrationTruth(rig.depth, rig.colour, rig.depthToColour, pose);
    Registration registration =
        registerDepth(depth, rig, rig.colour.intrinsics.width, rig.colour.intrinsics.height);
};

TEST(Registration, ColourPixelOfEachDepthPixelIsTheSyntheticRigsAnalyticCorrespondence) {
    const RigScene s;
    ASSERT_NE(s.rig.colour.lens.model, frame::LensModel::None); // distortion on
    std::vector<double> errors;
    const int width = s.registration.colourWidth;
    for (std::size_t i = 0; i < s.truth.colourPixel.size(); ++i) {
        const std::int32_t pixel = s.registration.colourPixel[i];
        if (!s.truth.visible[i] || pixel == Registration::kUnseen)
            continue;
        const auto [x, y] = s.truth.colourPixel[i];
        errors.push_back(std::hypot(pixel % width - x, pixel / width - y));
    }
    const auto visible = std::count(s.truth.visible.begin(), s.truth.visible.end(), 1);
    ASSERT_GT(visible, 848 * 480 / 3); // the colour camera sees about half of the depth camera's view
    EXPECT_GT(static_cast<double>(errors.size()), 0.99 * static_cast<double>(visible));
    EXPECT_LT(percentile(errors, 0.5), 0.5);
    EXPECT_LT(percentile(errors, 0.99), 1.0);
}

// Where the colour camera's view changes between two neighbouring depth pixels, the seen mask may be a
// pixel off (each sample covers its footprint in the z-buffer); everywhere else it is the scene's visibility.
TEST(Registration, SeenMaskIsTheSyntheticRigsVisibilityAwayFromItsEdges) {
    const RigScene s;
    const int w = s.depth.width, h = s.depth.height;
    int compared = 0, wrong = 0, hidden = 0;
    for (int v = 1; v + 1 < h; ++v)
        for (int u = 1; u + 1 < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * w + u;
            if (std::isnan(s.truth.colourPixel[i][0]))
                continue;
            bool edge = false;
            for (int dv = -1; dv <= 1; ++dv)
                for (int du = -1; du <= 1; ++du)
                    edge |= s.truth.visible[i + dv * w + du] != s.truth.visible[i];
            if (edge)
                continue;
            ++compared;
            hidden += !s.truth.visible[i];
            wrong += s.registration.seen.pixels[i] != s.truth.visible[i];
        }
    EXPECT_GT(hidden, 1000); // the colour camera's narrower view leaves the depth map's margins unseen
    EXPECT_GT(compared, w * h / 2);
    EXPECT_EQ(wrong, 0);
}

// A wall 2 m away with a 20 cm square 0.6 m in front of it, seen by a depth camera and by a colour camera
// 6 cm to its right (a wide baseline, so the square hides a broad strip of wall from the colour camera
// only). The colour image is the square in red over a green wall.
struct OccludedWall {
    static constexpr double kWallZ = 2.0, kSquareZ = 0.6, kHalfSide = 0.1, kBaseline = 0.06;
    frame::RigCalibration rig;
    frame::Frame frame;

    OccludedWall() {
        rig.depth.intrinsics = {150.0, 150.0, 79.5, 59.5, 160, 120};
        rig.colour.intrinsics = {280.0, 280.0, 159.5, 119.5, 320, 240};
        rig.colour.lens = {frame::LensModel::BrownConrady, {0.08, -0.1, 0.001, -0.001, 0.02}};
        rig.depthToColour.translationMeters = {-kBaseline, 0.0, 0.0};
        frame.rig = std::make_shared<const frame::RigCalibration>(rig);
        frame.cameraIntrinsics = rig.colour.intrinsics;
        frame.capturedImage = colourImage();
        frame::DepthData depth{frame::Plane<float>(160, 120), {}};
        for (int v = 0; v < 120; ++v)
            for (int u = 0; u < 160; ++u)
                depth.depthMeters.at(u, v) =
                    onSquare(u, v) ? static_cast<float>(kSquareZ) : static_cast<float>(kWallZ);
        frame.sceneDepth = std::move(depth);
    }
    static bool inSquare(double x, double y) { return std::abs(x) <= kHalfSide && std::abs(y) <= kHalfSide; }
    bool onSquare(int u, int v) const {
        const auto ray = frame::pixelRay(rig.depth, u, v);
        return inSquare(ray[0] * kSquareZ, ray[1] * kSquareZ);
    }
    // The analytic visibility of the wall behind depth pixel (u, v): the segment from the colour camera's
    // centre (kBaseline, 0, 0) to the wall point crosses the square's plane outside the square.
    bool wallHidden(int u, int v) const {
        const auto ray = frame::pixelRay(rig.depth, u, v);
        const double s = kSquareZ / kWallZ;
        return inSquare(kBaseline + (ray[0] * kWallZ - kBaseline) * s, ray[1] * kWallZ * s);
    }
    frame::CapturedImage colourImage() const {
        auto bytes = std::make_shared<std::vector<std::uint8_t>>(320 * 240 * 3);
        for (int y = 0; y < 240; ++y)
            for (int x = 0; x < 320; ++x) {
                const auto ray = frame::pixelRay(rig.colour, x, y); // colour frame = depth frame - baseline
                const bool red = inSquare(kBaseline + ray[0] * kSquareZ, ray[1] * kSquareZ);
                std::uint8_t* p = bytes->data() + (static_cast<std::size_t>(y) * 320 + x) * 3;
                p[0] = red ? 255 : 0;
                p[1] = red ? 0 : 200;
                p[2] = 0;
            }
        return {frame::PixelFormat::Rgb24, 320, 240, std::move(bytes)};
    }
};

TEST(Registration, WallHiddenByAForegroundObjectIsFlaggedUnseenAndNeverTakesItsColour) {
    const OccludedWall scene;
    CameraColourTable table;
    const PointColours colours = framePointColours(scene.frame, scene.frame.sceneDepth->depthMeters, table);
    ASSERT_TRUE(colours.seen);
    // 0: wall seen, 1: wall hidden, 2: the square itself.
    const auto status = [&](int u, int v) {
        return scene.onSquare(u, v) ? 2 : scene.wallHidden(u, v) ? 1 : 0;
    };
    int hidden = 0, compared = 0;
    for (int v = 1; v < 119; ++v)
        for (int u = 1; u < 159; ++u) {
            const std::uint8_t* rgb = &colours.colours->pixels[(static_cast<std::size_t>(v) * 160 + u) * 3];
            const bool seen = colours.seen->at(u, v) != 0;
            const int s = status(u, v);
            if (s == 2) {
                EXPECT_TRUE(seen && rgb[0] == 255 && rgb[1] == 0) << u << "," << v;
                continue;
            }
            if (seen)
                EXPECT_FALSE(rgb[0] > 128) << "wall point " << u << "," << v << " took the square's colour";
            else
                EXPECT_TRUE(rgb[0] == kUnseenGray && rgb[1] == kUnseenGray && rgb[2] == kUnseenGray);
            bool edge = false;
            for (int dv = -1; dv <= 1; ++dv)
                for (int du = -1; du <= 1; ++du)
                    edge |= status(u + du, v + dv) != s;
            if (edge)
                continue;
            ++compared;
            hidden += s == 1;
            EXPECT_EQ(seen, s == 0) << u << "," << v;
        }
    EXPECT_GT(hidden, 300); // a strip about 7 pixels wide along the square's height
    EXPECT_GT(compared, 10000);
}

// The hover readout of a cloud coloured on the GPU asks about one sample: the answer is the seen mask's,
// hidden wall and square alike.
TEST(Registration, OneSamplesVisibilityIsTheSeenMasks) {
    const OccludedWall scene;
    CameraColourTable table;
    const frame::Plane<float>& depth = scene.frame.sceneDepth->depthMeters;
    const PointColours colours = framePointColours(scene.frame, depth, table);
    int hidden = 0;
    for (int v = 0; v < depth.height; v += 3)
        for (int u = 0; u < depth.width; u += 2) {
            const bool seen = colours.seen->at(u, v) != 0;
            hidden += !seen;
            ASSERT_EQ(sampleSeenByColour(scene.frame, depth, scene.frame.depthIntrinsics(), u, v), seen)
                << u << "," << v;
        }
    EXPECT_GT(hidden, 50);
}

// A strong barrel lens folds points from far outside its view back into the picture (k1 = -0.5: an ideal
// radius of 1.25 images at 0.27, well inside). Those points are not seen, whatever the polynomial says.
TEST(Registration, PointsFarOutsideTheColourLensesViewAreNotFoldedBackIntoTheImage) {
    frame::RigCalibration rig;
    rig.depth.intrinsics = {40.0, 40.0, 99.5, 99.5, 200, 200}; // about 136 degrees across
    rig.colour.intrinsics = {400.0, 400.0, 99.5, 99.5, 200, 200};
    rig.colour.lens = {frame::LensModel::BrownConrady, {-0.5, 0.0, 0.0, 0.0, 0.0}};
    const frame::Plane<float> wall(200, 200, 2.0f);
    const Registration r = registerDepth(wall, rig, 200, 200);
    int folding = 0, seenFarOut = 0, seen = 0;
    for (int v = 0; v < 200; ++v)
        for (int u = 0; u < 200; ++u) {
            const auto ray = frame::pixelRay(rig.depth, u, v);
            const double radius = std::hypot(ray[0], ray[1]);
            const auto pixel = frame::projectPoint(rig.colour, ray);
            const bool lands =
                pixel && (*pixel)[0] >= 0 && (*pixel)[0] < 200 && (*pixel)[1] >= 0 && (*pixel)[1] < 200;
            folding += radius > 1.0 && lands;
            seenFarOut += radius > 1.0 && r.seen.at(u, v);
            seen += r.seen.at(u, v);
        }
    ASSERT_GT(folding, 100) << "the lens does fold points back in";
    EXPECT_EQ(seenFarOut, 0);
    EXPECT_GT(seen, 100) << "the points truly in view are seen";
}

TEST(Registration, SingleCameraColoursAreTodaysPointColorsBitForBit) {
    devices::SyntheticDevice device(
        {.depthWidth = 256, .depthHeight = 192, .cameraWidth = 640, .cameraHeight = 480});
    ASSERT_TRUE(device.open());
    const frame::FramePtr frame = device.makeFrame(0, 0.0);
    const frame::Plane<float>& depth = frame->sceneDepth->depthMeters;
    const RgbImage today = pointColours(frame->capturedImage, depth.width, depth.height);

    CameraColourTable table;
    const PointColours none = framePointColours(*frame, depth, table);
    EXPECT_EQ(none.colours->pixels, today.pixels);
    EXPECT_FALSE(none.seen);

    // The same camera written as a rig: R = I, t = 0, one lens, the depth intrinsics the image's scaled.
    frame::Frame asRig = *frame;
    frame::RigCalibration rig;
    rig.colour.intrinsics = frame->cameraIntrinsics;
    rig.depth.intrinsics = frame->cameraIntrinsics.scaledTo(depth.width, depth.height);
    asRig.rig = std::make_shared<const frame::RigCalibration>(rig);
    EXPECT_TRUE(isSingleCamera(rig));
    const PointColours identity = framePointColours(asRig, depth, table);
    EXPECT_EQ(identity.colours->pixels, today.pixels);
    EXPECT_FALSE(identity.seen);
    EXPECT_EQ(asRig.depthIntrinsics().fx, frame->depthIntrinsics().fx);

    rig.depthToColour.translationMeters[0] = 0.01;
    EXPECT_FALSE(isSingleCamera(rig));
}

// The depth map aligned to the colour image is the depth the colour sensor itself would measure: the
// scene's exact depth through the colour lens, wherever the depth sensor sees that surface too (the scene
// tells which colour pixels it does). Pixels within two of a depth edge are left out (a sample covers its
// footprint, so a nearer surface may reach a pixel further there).
TEST(AlignedDepth, IsTheDepthTheColourSensorWouldSeeThroughItsLens) {
    const RigScene s;
    const int w = s.rig.colour.intrinsics.width, h = s.rig.colour.intrinsics.height;
    const frame::Plane<float> aligned = alignDepthToColour(s.depth, s.rig, w, h);
    ASSERT_EQ(aligned.width, w);
    ASSERT_EQ(aligned.height, h);
    const frame::Pose colourPose = devices::colourSensorPose(s.pose, s.rig.depthToColour);
    const frame::Plane<float> truth = s.scene.trueDepth(s.rig.colour, colourPose);
    // The same question the other way round: which colour pixels' surfaces the depth sensor sees.
    const devices::RegistrationTruth seenByDepth =
        s.scene.registrationTruth(s.rig.colour, s.rig.depth, frame::inverse(s.rig.depthToColour), colourPose);
    const auto nearEdge = [&](int x, int y) {
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
                if (std::abs(truth.at(nx, ny) - truth.at(x, y)) > 0.03f * truth.at(x, y) ||
                    !seenByDepth.visible[static_cast<std::size_t>(ny) * w + nx])
                    return true;
            }
        return false;
    };
    std::vector<double> relative;
    int withTruth = 0, holes = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (truth.at(x, y) <= 0.0f || nearEdge(x, y) ||
                !seenByDepth.visible[static_cast<std::size_t>(y) * w + x])
                continue;
            ++withTruth;
            if (aligned.at(x, y) <= 0.0f) {
                ++holes;
                continue;
            }
            relative.push_back(std::abs(aligned.at(x, y) - truth.at(x, y)) / truth.at(x, y));
        }
    ASSERT_GT(withTruth, w * h / 2);
    // The colour image is twice as fine as the depth map: without each sample covering its footprint three
    // pixels in four would be holes; with it, a gap is a rare slanted spot.
    EXPECT_LT(holes, withTruth / 10000);
    // Measured: median 0.03 %, 99th percentile 0.3 %; the same without the colour lens's distortion is
    // 0.12 % and 0.85 %.
    EXPECT_LT(percentile(relative, 0.5), 0.001);
    EXPECT_LT(percentile(relative, 0.99), 0.005);
}

// The raw frame's cloud (export's PLY, accumulation of raw frames) is coloured the same registered way.
TEST(Registration, TheRawFramesCloudOfATwoSensorFrameTakesTheRegisteredColours) {
    devices::SyntheticDevice device(dc::test::smallRigConfig());
    ASSERT_TRUE(device.open());
    const frame::FramePtr frame = device.makeFrame(0, 0.0);
    CameraColourTable table;
    const PointColours colours = framePointColours(*frame, frame->sceneDepth->depthMeters, table);
    const auto fromFrame = buildPointCloud(*frame, frame::Confidence::Low, 0.0f);
    const auto registered = buildPointCloud(
        {&*frame->sceneDepth, frame->depthIntrinsics(), colours.colours.get()}, frame::Confidence::Low, 0.0f);
    ASSERT_EQ(fromFrame.size(), registered.size());
    ASSERT_FALSE(fromFrame.empty());
    for (std::size_t i = 0; i < fromFrame.size(); ++i)
        ASSERT_TRUE(fromFrame[i].r == registered[i].r && fromFrame[i].g == registered[i].g &&
                    fromFrame[i].b == registered[i].b)
            << i;
}

TEST(SyntheticRig, FramesCarryTheRigAndEachSensorsOwnImage) {
    auto device = devices::openSourceSpec("synthetic:rig=rgbd");
    ASSERT_TRUE(device);
    auto* synthetic = dynamic_cast<devices::SyntheticDevice*>(device->get());
    ASSERT_NE(synthetic, nullptr);
    ASSERT_TRUE(synthetic->open());
    const frame::FramePtr frame = synthetic->makeFrame(0, 0.0);
    ASSERT_TRUE(frame->rig);
    EXPECT_EQ(frame->capturedImage.width, 1280);
    EXPECT_EQ(frame->capturedImage.height, 720);
    EXPECT_EQ(frame->sceneDepth->depthMeters.width, 848);
    EXPECT_EQ(frame->sceneDepth->depthMeters.height, 480);
    EXPECT_EQ(frame->depthIntrinsics().fx, frame->rig->depth.intrinsics.fx);
    EXPECT_EQ(frame->cameraIntrinsics.fx, frame->rig->colour.intrinsics.fx);
    // Depth about 87 x 57 degrees, colour about 69 x 42.
    const auto fov = [](double f, int size) { return 2.0 * std::atan(0.5 * size / f) * 180.0 / M_PI; };
    EXPECT_NEAR(fov(frame->rig->depth.intrinsics.fx, 848), 87.0, 0.5);
    EXPECT_NEAR(fov(frame->rig->colour.intrinsics.fx, 1280), 69.0, 0.5);
    EXPECT_NEAR(fov(frame->rig->colour.intrinsics.fy, 720), 42.0, 0.5);

    auto bad = devices::openSourceSpec("synthetic:rig=stereo");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("rig"), std::string::npos);
}

} // namespace
} // namespace dc::processing
