// Guided upsampling against the synthetic scene's exact depth, and the upsampling stage's contract.

#include "devices/synthetic/synthetic_device.h"
#include "devices/synthetic/synthetic_scene.h"
#include "processing/camera_image.h"
#include "processing/guided_filter.h"
#include "processing/pipeline.h"
#include "processing/quality.h"
#include "processing/registration.h"
#include "processing/upsampling_stage.h"
#include "tests/small_rig.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dc::processing {
namespace {

using frame::Plane;

// The desk scene as an ARKit-like frame at a test-friendly size: 256x192 depth, 960x720 camera.
struct Scene {
    frame::FramePtr frame;
    Plane<float> truth; // at half the camera size
};

const Scene& desk() {
    static const Scene scene = [] {
        const devices::SyntheticScene s;
        const frame::Pose pose = devices::SyntheticScene::cameraPose(0.0, false);
        const frame::Intrinsics camera = devices::SyntheticScene::cameraIntrinsics(960, 720);
        auto f = std::make_shared<frame::Frame>();
        f->capturedImage = s.renderImage(camera, pose);
        f->cameraIntrinsics = camera;
        f->sceneDepth = s.sensorDepth(camera.scaledTo(256, 192), pose, 3);
        return Scene{f, s.trueDepth(camera.scaledTo(480, 360), pose)};
    }();
    return scene;
}

GuidedFilterParams deskParams(int subsample) {
    GuidedFilterParams p; // the default's 8 output pixels at 3.75x, scaled to this 1.9x upsampling
    p.radius = 4;
    p.subsample = subsample;
    p.fitNoise = 0.005f;
    return p;
}

frame::DepthData upsampleDesk(const GuidedFilterParams& p) {
    std::vector<std::uint8_t> scratch;
    return guidedUpsample(*desk().frame->sceneDepth, lumaView(desk().frame->capturedImage, scratch), 480, 360,
                          p);
}

// Plain bilinear interpolation with aligned pixel centres (where the footprint is measured).
Plane<float> bilinear(const Plane<float>& low, int width, int height) {
    Plane<float> out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double sx = std::clamp((x + 0.5) * low.width / width - 0.5, 0.0, low.width - 1.0);
            const double sy = std::clamp((y + 0.5) * low.height / height - 0.5, 0.0, low.height - 1.0);
            const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
            const int x1 = std::min(x0 + 1, low.width - 1), y1 = std::min(y0 + 1, low.height - 1);
            const double fx = sx - x0, fy = sy - y0;
            out.at(x, y) = static_cast<float>((1 - fy) * ((1 - fx) * low.at(x0, y0) + fx * low.at(x1, y0)) +
                                              fy * ((1 - fx) * low.at(x0, y1) + fx * low.at(x1, y1)));
        }
    return out;
}

TEST(GuidedUpsampling, BeatsInterpolationAgainstExactDepth) {
    const Plane<std::uint8_t> mask = [] {
        Plane<std::uint8_t> m = measuredFootprint(desk().frame->sceneDepth->depthMeters, 480, 360);
        for (std::size_t i = 0; i < m.pixels.size(); ++i)
            m.pixels[i] = m.pixels[i] && desk().truth.pixels[i] > 0.0f;
        return m;
    }();
    const DepthError interpolated =
        depthError(bilinear(desk().frame->sceneDepth->depthMeters, 480, 360), desk().truth, &mask);
    ASSERT_GT(interpolated.count, 100000u);
    for (int s : {1, 2, 4}) {
        const DepthError guided = depthError(upsampleDesk(deskParams(s)).depthMeters, desk().truth, &mask);
        EXPECT_LT(guided.mad, 0.8 * interpolated.mad) << "subsample " << s;
        EXPECT_LT(guided.rmse, interpolated.rmse) << "subsample " << s;
    }
    // At 1.9x, s = 8 puts the coefficients on a grid 4x coarser than the sensor's own map: faster, but it
    // cannot beat interpolation there; it must still be a sane upsampling.
    const DepthError coarse = depthError(upsampleDesk(deskParams(8)).depthMeters, desk().truth, &mask);
    EXPECT_LT(coarse.mad, 2.0 * interpolated.mad);
}

// The rig's first frame at a test-friendly size: the small rig's 212x120 depth, with a 640x360 colour image
// (a guide finer than the depth, as upsampling has on real rigs).
struct RigScene {
    devices::SyntheticDevice device{[] {
        devices::SyntheticConfig c = test::smallRigConfig();
        c.cameraWidth = 640;
        c.cameraHeight = 360;
        return c;
    }()};
    frame::FramePtr frame;
};

// Full-camera-size upsampling's error against the exact depth of the depth sensor's view, where the depth
// sensor measured and the rig's colour camera sees (elsewhere a rig has nothing to guide with).
DepthError rigUpsamplingError(const RigScene& scene, const frame::FramePtr& frame, UpsamplingMethod method) {
    ProcessingSettings settings;
    settings.upsampling = true;
    settings.upsamplingParams.method = method;
    settings.upsamplingParams.size = UpsamplingSize::FullCamera;
    UpsamplingStage stage;
    const frame::FramePtr out = stage.process(frame, settings);
    const Plane<float>& up = out->sceneDepth->depthMeters;
    EXPECT_GT(up.width, frame->sceneDepth->depthMeters.width);
    const Plane<float> truth =
        scene.device.scene().trueDepth(out->depthIntrinsicsAt(up.width, up.height), frame->pose.value());
    const Plane<std::uint8_t> seen = registerDepth(truth, *scene.frame->rig, 640, 360).seen;
    Plane<std::uint8_t> mask = measuredFootprint(frame->sceneDepth->depthMeters, up.width, up.height);
    for (std::size_t i = 0; i < mask.pixels.size(); ++i)
        mask.pixels[i] = mask.pixels[i] && truth.pixels[i] > 0.0f && seen.pixels[i];
    return depthError(up, truth, &mask);
}

// The criterion, like for like: the same noisy depth map upsampled with the rig's colour image
// aligned to the depth sensor as the guide, and with the image of an ideal single camera in the depth
// sensor's place (no baseline, no lens distortion, the depth sensor's view at the same output size). The
// registered guide must score within 10 % of the ideal one; the colour sensor's own view as the guide
// would put its edges beside the depth edges.
TEST(UpsamplingStage, OnATwoSensorRigScoresWithinTenPercentOfOneCamera) {
    RigScene scene;
    ASSERT_TRUE(scene.device.open());
    scene.frame = scene.device.makeFrame(0, 0.0);
    ASSERT_TRUE(scene.frame->rig);
    auto single = std::make_shared<frame::Frame>(*scene.frame);
    single->rig = nullptr;
    single->cameraIntrinsics = scene.frame->rig->depth.intrinsics.scaledTo(640, 362);
    single->capturedImage = scene.device.scene().renderImage(single->cameraIntrinsics, single->pose.value());
    // The default guided filter meets the criterion (about 4 % above the ideal guide; the colour sensor's
    // own view as the guide is about 13 % above).
    const DepthError ideal = rigUpsamplingError(scene, single, UpsamplingMethod::Fast);
    const DepthError registered = rigUpsamplingError(scene, scene.frame, UpsamplingMethod::Fast);
    ASSERT_GT(registered.count, 50000u);
    EXPECT_LT(registered.mad, 1.1 * ideal.mad) << "rig " << registered.mad << " m, one camera " << ideal.mad;
    // The real-time global smoother meets it too (about 4 % above the ideal guide).
    const DepthError idealGlobal = rigUpsamplingError(scene, single, UpsamplingMethod::Global);
    const DepthError registeredGlobal = rigUpsamplingError(scene, scene.frame, UpsamplingMethod::Global);
    EXPECT_LT(registeredGlobal.mad, 1.1 * idealGlobal.mad)
        << "rig " << registeredGlobal.mad << " m, one camera " << idealGlobal.mad;
}

// Whether `pred` holds for the 3x3 sensor pixels around (sx, sy), clamped to the map.
template <class T, class Pred> bool allAround(const Plane<T>& plane, int sx, int sy, Pred pred) {
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            if (!pred(plane.at(std::clamp(sx + dx, 0, plane.width - 1),
                               std::clamp(sy + dy, 0, plane.height - 1))))
                return false;
    return true;
}

TEST(GuidedUpsampling, HolesStayHolesAndConfidenceFollowsTheMap) {
    const frame::DepthData out = upsampleDesk(deskParams(4));
    const frame::DepthData& in = *desk().frame->sceneDepth;
    ASSERT_EQ(out.confidence.width, 480);
    ASSERT_EQ(out.confidence.height, 360);
    std::size_t holes = 0, confident = 0;
    for (int y = 0; y < 360; ++y)
        for (int x = 0; x < 480; ++x) {
            const float d = out.depthMeters.at(x, y);
            ASSERT_TRUE(std::isfinite(d) && d >= 0.0f);
            const int sx = x * 256 / 480, sy = y * 192 / 360; // the sensor pixel this one lies in
            if (allAround(in.depthMeters, sx, sy, [](float v) { return v == 0.0f; })) {
                EXPECT_EQ(d, 0.0f) << "no depth is invented in a hole, at " << x << "," << y;
                ++holes;
            }
            if (allAround(in.confidence, sx, sy, [](std::uint8_t c) { return c == 2; })) {
                EXPECT_EQ(out.confidence.at(x, y), 2) << x << "," << y;
                ++confident;
            }
        }
    EXPECT_GT(holes, 1000u) << "the scene's window has no depth";
    EXPECT_GT(confident, 10000u);
}

TEST(UpsamplingStage, OutputsOnePointPerOutputPixelWithScaledIntrinsics) {
    UpsamplingStage stage;
    ProcessingSettings settings;
    settings.upsampling = true;
    const frame::FramePtr out = stage.process(desk().frame, settings);
    ASSERT_TRUE(out->sceneDepth);
    EXPECT_EQ(out->sceneDepth->depthMeters.width, 480) << "half of the 960x720 camera";
    EXPECT_EQ(out->sceneDepth->depthMeters.height, 360);
    EXPECT_DOUBLE_EQ(out->depthIntrinsics().fx, desk().frame->cameraIntrinsics.fx / 2);
    settings.upsamplingParams.size = UpsamplingSize::FullCamera;
    settings.upsamplingParams.method = UpsamplingMethod::Full;
    EXPECT_EQ(stage.process(desk().frame, settings)->sceneDepth->depthMeters.width, 960);
}

TEST(UpsamplingStage, UpsamplesOnlyTheShownDepth) {
    UpsamplingStage stage;
    ProcessingSettings settings;
    settings.upsampling = true;
    auto f = std::make_shared<frame::Frame>(*desk().frame);
    f->smoothedSceneDepth = f->sceneDepth;
    const frame::FramePtr smoothedShown = stage.process(f, settings);
    EXPECT_EQ(smoothedShown->smoothedSceneDepth->depthMeters.width, 480);
    EXPECT_EQ(smoothedShown->sceneDepth->depthMeters.width, 256) << "not shown: left at the sensor's size";
    settings.depthSource = DepthSource::Raw;
    const frame::FramePtr rawShown = stage.process(f, settings);
    EXPECT_EQ(rawShown->sceneDepth->depthMeters.width, 480);
    EXPECT_EQ(rawShown->smoothedSceneDepth->depthMeters.width, 256);
}

TEST(UpsamplingStage, FramesWithoutCameraImagePassThrough) {
    UpsamplingStage stage;
    ProcessingSettings settings;
    settings.upsampling = true;
    auto f = std::make_shared<frame::Frame>(*desk().frame);
    f->capturedImage = {};
    const frame::FramePtr in = f;
    EXPECT_EQ(stage.process(in, settings), in);
}

TEST(UpsamplingStage, IsWantedOnlyWhenOnAndDepthIsShown) {
    const UpsamplingStage stage;
    ProcessingSettings settings;
    EXPECT_FALSE(stage.wanted(settings, {}));
    settings.upsampling = true;
    EXPECT_TRUE(stage.wanted(settings, {}));
    EXPECT_FALSE(stage.wanted(settings, {false, false, false, true, false, false}));
}

} // namespace
} // namespace dc::processing
