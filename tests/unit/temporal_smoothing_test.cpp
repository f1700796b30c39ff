#include "devices/synthetic/synthetic_scene.h"
#include "processing/pipeline.h"
#include "processing/quality.h"
#include "processing/smoothing_stage.h"
#include "processing/temporal_smoothing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dc::processing {
namespace {

using frame::DepthData;
using frame::Plane;

DepthData uniform(int w, int h, float meters) {
    return {Plane<float>(w, h, meters), Plane<std::uint8_t>(w, h, 2)};
}

std::vector<DepthData> staticSyntheticScene(int frames) {
    const devices::SyntheticScene scene;
    const frame::Intrinsics k = devices::SyntheticScene::cameraIntrinsics(256, 192);
    const frame::Pose pose = devices::SyntheticScene::cameraPose(0.0, false);
    std::vector<DepthData> out;
    for (int i = 0; i < frames; ++i)
        out.push_back(scene.sensorDepth(k, pose, static_cast<std::uint64_t>(i)));
    return out;
}

TEST(TemporalSmoothing, ReducesFlickerOfAStaticSceneAtLeastThreefoldAtAlpha04) {
    SmoothingParams params;
    params.alpha = 0.4f;
    const TemporalNoise noise = measureTemporalNoise(staticSyntheticScene(24), params, 8);
    ASSERT_GT(noise.pixels, 20000u) << "most of the scene is measured with confidence in every frame";
    // An exponential average with weight a leaves a^2 / (2 - a) of the frame-to-frame difference variance:
    // 0.1 at a = 0.4, i.e. 3.16x less flicker; the per-pixel spread drops by sqrt((2 - a) / a) = 2x.
    EXPECT_GE(noise.rawFlicker / noise.smoothedFlicker, 3.0);
    EXPECT_GE(noise.rawSpread / noise.smoothedSpread, 1.8); // ~2 measured over a long sequence
}

TEST(TemporalSmoothing, AMovingDepthStepLagsAtMostTwoFrames) {
    const SmoothingParams params; // alpha 0.4, jump 0.10 m
    EXPECT_EQ(measureStepLag(0.5f, params), 0) << "a jump beyond the threshold restarts the pixel at once";
    EXPECT_LE(measureStepLag(0.05f, params), 2) << "a step below the threshold is averaged in quickly";
    SmoothingParams noJumpReset = params;
    noJumpReset.jumpMeters = 10.0f;
    EXPECT_GT(measureStepLag(0.5f, noJumpReset), 0) << "the lag test can see a lag";
}

TEST(TemporalSmoothing, BlendsSmallChangesAndRestartsAtJumps) {
    TemporalSmoother s;
    const SmoothingParams params; // alpha 0.4, jump 0.10 m
    s.smooth(uniform(2, 2, 1.0f), params);
    EXPECT_NEAR(s.smooth(uniform(2, 2, 1.05f), params).depthMeters.at(0, 0), 1.02f, 1e-6f);
    EXPECT_FLOAT_EQ(s.smooth(uniform(2, 2, 2.0f), params).depthMeters.at(1, 1), 2.0f);
}

TEST(TemporalSmoothing, HolesKeepTheirValueForHoleFramesThenClear) {
    TemporalSmoother s;
    SmoothingParams params;
    params.holeFrames = 2;
    s.smooth(uniform(1, 1, 1.5f), params);
    const float invalid[] = {0.0f, std::numeric_limits<float>::quiet_NaN(), -1.0f};
    EXPECT_FLOAT_EQ(s.smooth(uniform(1, 1, invalid[0]), params).depthMeters.pixels[0], 1.5f);
    EXPECT_FLOAT_EQ(s.smooth(uniform(1, 1, invalid[1]), params).depthMeters.pixels[0], 1.5f);
    EXPECT_EQ(s.smooth(uniform(1, 1, invalid[2]), params).depthMeters.pixels[0], 0.0f);
}

TEST(TemporalSmoothing, NonFiniteInputNeverReachesTheOutput) {
    TemporalSmoother s;
    DepthData d = uniform(4, 1, 1.0f);
    d.depthMeters.pixels = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                            -std::numeric_limits<float>::infinity(), 2.0f};
    for (int i = 0; i < 5; ++i)
        for (float v : s.smooth(d, {}).depthMeters.pixels)
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
}

TEST(TemporalSmoothing, AResolutionChangeRestarts) {
    TemporalSmoother s;
    s.smooth(uniform(4, 4, 1.0f), {});
    EXPECT_FLOAT_EQ(s.smooth(uniform(8, 6, 1.05f), {}).depthMeters.at(7, 5), 1.05f);
}

frame::FramePtr frameAt(std::int64_t timestampNs, float meters) {
    auto f = std::make_shared<frame::Frame>();
    f->timestampNs = timestampNs;
    f->sceneDepth = uniform(4, 4, meters);
    return f;
}

TEST(SmoothingStage, RestartsWhenTimeRunsBackwardsOrJumpsAhead) {
    SmoothingStage stage;
    ProcessingSettings settings;
    settings.smoothing = true;
    stage.process(frameAt(1'000'000'000, 1.0f), settings);
    EXPECT_LT(
        stage.process(frameAt(1'016'000'000, 1.05f), settings)->smoothedSceneDepth->depthMeters.at(0, 0),
        1.05f)
        << "consecutive frames blend";
    EXPECT_FLOAT_EQ(
        stage.process(frameAt(500'000'000, 1.05f), settings)->smoothedSceneDepth->depthMeters.at(0, 0), 1.05f)
        << "a seek backwards restarts the history";
    stage.process(frameAt(516'000'000, 1.0f), settings);
    EXPECT_FLOAT_EQ(
        stage.process(frameAt(5'000'000'000, 1.05f), settings)->smoothedSceneDepth->depthMeters.at(0, 0),
        1.05f)
        << "a seek forwards restarts the history";
}

TEST(SmoothingStage, ARedoOfTheSameFrameStartsFromTheHistoryBeforeIt) {
    SmoothingStage stage;
    ProcessingSettings settings;
    settings.smoothing = true;
    settings.smoothingParams.alpha = 0.4f;
    stage.process(frameAt(1'000'000'000, 1.0f), settings);
    const frame::FramePtr second = frameAt(1'016'000'000, 1.05f);
    const auto at = [&](const ProcessingSettings& s) {
        return stage.process(second, s)->smoothedSceneDepth->depthMeters.at(0, 0);
    };
    EXPECT_NEAR(at(settings), 1.02f, 1e-6f);
    EXPECT_NEAR(at(settings), 1.02f, 1e-6f) << "the same frame again is no new frame";
    settings.smoothingParams.alpha = 1.0f;
    EXPECT_NEAR(at(settings), 1.05f, 1e-6f) << "new parameters apply to the history before the frame";
    settings.smoothingParams.alpha = 0.4f;
    EXPECT_NEAR(stage.process(frameAt(1'032'000'000, 1.05f), settings)->smoothedSceneDepth->depthMeters.at(0, 0),
                1.05f, 1e-6f)
        << "the next frame continues from the redone one";
}

TEST(SmoothingStage, PassesASourcesOwnSmoothedDepthThrough) {
    SmoothingStage stage;
    auto f = std::make_shared<frame::Frame>(*frameAt(0, 1.0f));
    f->smoothedSceneDepth = uniform(4, 4, 3.0f);
    const frame::FramePtr in = f;
    EXPECT_EQ(stage.process(in, {}), in);
}

TEST(SmoothingStage, RunsOnlyWhileTheSmoothedDepthIsShown) {
    const SmoothingStage stage;
    ProcessingSettings settings;
    settings.smoothing = true;
    EXPECT_TRUE(stage.wanted(settings, {}));
    settings.depthSource = DepthSource::Raw;
    EXPECT_FALSE(stage.wanted(settings, {}));
    settings.depthSource = DepthSource::Smoothed;
    Needs nothingShown{false, false, false, true, false, false, false};
    EXPECT_FALSE(stage.wanted(settings, nothingShown));
    nothingShown.fogPanel = true;
    EXPECT_TRUE(stage.wanted(settings, nothingShown)) << "fog shows depth";
}

} // namespace
} // namespace dc::processing
