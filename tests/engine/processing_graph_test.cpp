// The processing graph counts the work it does: each test states which stages a run must (and must not)
// make again, so a memo that stops hitting, or a stage that runs for nobody, fails here.

#include "engine/processing_graph.h"
#include "engine_test_support.h"
#include "frame/jpeg_codec.h"
#include "processing/aura.h"
#include "processing/camera_image.h"
#include "processing/confidence_estimator.h"
#include "processing/decimation.h"
#include "processing/edge_alignment.h"
#include "processing/fog.h"
#include "processing/registration.h"
#include "tests/small_rig.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace dc::engine::test {
namespace {

using Runs = std::map<std::string, std::uint64_t, std::less<>>;

// Every product on: the cloud in camera colours, all panels, fog, aura, the automatic range, smoothing and
// upsampling.
Demand everything() {
    Demand d;
    d.cameraPanelWidth = 320;
    d.fog = true;
    d.aura = true;
    d.automaticRange = true;
    d.processing.smoothing = true;
    d.processing.upsampling = true;
    return d;
}

// Only the cloud, coloured by depth: nothing reads confidence or the camera.
Demand cloudOnly() {
    Demand d;
    d.pointColours = false;
    d.depthImage = false;
    d.confidencePanel = false;
    return d;
}

// The stages whose count differs between two snapshots, with how many more runs each made.
Runs ranSince(const Runs& before, const Runs& after) {
    Runs delta;
    for (const auto& [stage, n] : after) {
        const auto it = before.find(stage);
        const std::uint64_t was = it == before.end() ? 0 : it->second;
        if (n != was)
            delta[stage] = n - was;
    }
    return delta;
}

class ProcessingGraphTest : public ::testing::Test {
protected:
    // Frames without sensor confidence, so the confidence estimate has work whenever it is wanted.
    void SetUp() override {
        for (const frame::FramePtr& f : syntheticFrames(2))
            frames_.push_back(withoutConfidence(f));
    }

    // Runs `demand` on frame `index` and returns what ran for it.
    Runs runOn(std::size_t index, const Demand& demand, bool newFrame = false) {
        const Runs before = graph_.allRuns();
        last_ = graph_.run(frames_[index], demand, ++generation_, newFrame);
        return ranSince(before, graph_.allRuns());
    }

    std::vector<frame::FramePtr> frames_;
    ProcessingGraph graph_;
    processing::ShownFramePtr last_;
    std::uint64_t generation_ = 0;
};

TEST_F(ProcessingGraphTest, EveryStageRunsOnceForANewFrameWithEverythingShown) {
    const Runs ran = runOn(0, everything(), true);
    const Runs expected{{std::string(processing::kConfidenceEstimateStage), 1},
                        {std::string(processing::kSmoothingStage), 1},
                        {std::string(processing::kUpsamplingStage), 1},
                        {std::string(kPointColoursStage), 1},
                        {std::string(kCameraImageStage), 1},
                        {std::string(kEffectsImageStage), 1},
                        {std::string(kFogStage), 1},
                        {std::string(kAuraStage), 1},
                        {std::string(kDepthRangeStage), 1},
                        {std::string(kPointCountStage), 1}};
    EXPECT_EQ(ran, expected);
    ASSERT_TRUE(last_->depth.data);
    EXPECT_TRUE(last_->depth.upsampled);
    EXPECT_TRUE(last_->depth.smoothed);
    EXPECT_TRUE(last_->pointColours && last_->cameraImage && last_->fog && last_->aura);
    EXPECT_TRUE(last_->automaticRange);
    EXPECT_GT(last_->pointCount, 0u);
}

// What a colormap change (which lives in the shader, not in the demand) or a redraw asks of the graph.
TEST_F(ProcessingGraphTest, TheSameFrameAndDemandRunNothingAgainAndShareEveryProduct) {
    runOn(0, everything(), true);
    const processing::ShownFramePtr first = last_;
    EXPECT_EQ(runOn(0, everything()), Runs{});
    EXPECT_EQ(last_->depth.data, first->depth.data);
    EXPECT_EQ(last_->pointColours, first->pointColours);
    EXPECT_EQ(last_->cameraImage, first->cameraImage);
    EXPECT_EQ(last_->fog, first->fog);
    EXPECT_EQ(last_->aura, first->aura);
    EXPECT_EQ(last_->pointCount, first->pointCount);
    EXPECT_TRUE(last_->timings.empty());
}

TEST_F(ProcessingGraphTest, AFogSettingRerunsOnlyTheFog) {
    runOn(0, everything(), true);
    Demand d = everything();
    d.processing.fog.fogMaxMeters = 2.0f;
    EXPECT_EQ(runOn(0, d), (Runs{{std::string(kFogStage), 1}}));
}

TEST_F(ProcessingGraphTest, AConfidenceLevelRerunsOnlyThePointCount) {
    runOn(0, everything(), true);
    const std::size_t all = last_->pointCount;
    Demand d = everything();
    d.minConfidence = frame::Confidence::High;
    EXPECT_EQ(runOn(0, d), (Runs{{std::string(kPointCountStage), 1}}));
    EXPECT_LT(last_->pointCount, all);
}

TEST_F(ProcessingGraphTest, UpsamplingOffRerunsTheDepthAndItsReadersButNotTheCameraImages) {
    runOn(0, everything(), true);
    const int upsampledWidth = last_->depth.width();
    Demand d = everything();
    d.processing.upsampling = false;
    // The depth pipeline runs again on the same capture (smoothing redoes it without advancing history), and
    // everything read from the shown depth follows; the camera's own images stay.
    const Runs expected{{std::string(processing::kConfidenceEstimateStage), 1},
                        {std::string(processing::kSmoothingStage), 1},
                        {std::string(kPointColoursStage), 1},
                        {std::string(kFogStage), 1},
                        {std::string(kAuraStage), 1},
                        {std::string(kDepthRangeStage), 1},
                        {std::string(kPointCountStage), 1}};
    EXPECT_EQ(runOn(0, d), expected);
    EXPECT_EQ(last_->depth.width(), frames_[0]->sceneDepth->depthMeters.width);
    EXPECT_NE(last_->depth.width(), upsampledWidth);
    EXPECT_FALSE(last_->depth.upsampled);
}

TEST_F(ProcessingGraphTest, TheCameraPanelIsRemadeOnlyWhenItsShownSizeCrossesAStep) {
    runOn(0, everything(), true);
    Demand d = everything();
    d.cameraPanelWidth = 300; // the same 64-pixel step as 320
    EXPECT_EQ(runOn(0, d), Runs{});
    d.cameraPanelWidth = 100;
    EXPECT_EQ(runOn(0, d), (Runs{{std::string(kCameraImageStage), 1}}));
    EXPECT_EQ(last_->cameraImage->width, processing::cameraPanelImageSize(frames_[0]->capturedImage, 100)[0]);
}

// The depth and confidence panels shown at a third of the map's width read every third sample: the graph
// picks them (the GL thread only uploads them), once per shown depth and step.
TEST_F(ProcessingGraphTest, PanelsShownSmallerThanTheMapGetTheirSamplesPickedOncePerStep) {
    Demand d = everything();
    runOn(0, d, true);
    EXPECT_EQ(last_->panelSamples, nullptr) << "an unknown panel width draws the map whole";
    const int width = last_->depth.width();
    d.dataPanelWidth = width / 3;
    EXPECT_EQ(runOn(0, d), (Runs{{std::string(kPanelSamplesStage), 1}}));
    ASSERT_NE(last_->panelSamples, nullptr);
    EXPECT_EQ(last_->panelStep, 3);
    const frame::DepthData expected = processing::sampleCellCentres(*last_->depth.data, 3);
    EXPECT_EQ(last_->panelSamples->depthMeters.pixels, expected.depthMeters.pixels);
    EXPECT_EQ(last_->panelSamples->confidence.pixels, expected.confidence.pixels);
    d.dataPanelWidth = width / 3 - 1; // a little narrower: still every third sample
    EXPECT_EQ(runOn(0, d), Runs{});
    d.dataPanelWidth = width / 2;
    EXPECT_EQ(runOn(0, d), (Runs{{std::string(kPanelSamplesStage), 1}}));
    EXPECT_EQ(last_->panelStep, 2);
    d.dataPanelWidth = width;
    EXPECT_EQ(runOn(0, d), Runs{});
    EXPECT_EQ(last_->panelSamples, nullptr) << "shown whole";
    d.dataPanelWidth = width / 3;
    d.depthImage = false;
    d.confidencePanel = false;
    runOn(0, d);
    EXPECT_EQ(last_->panelSamples, nullptr) << "no panel shows them";
}

TEST_F(ProcessingGraphTest, AStageWhoseOutputNobodyReadsNeverRuns) {
    for (std::size_t i = 0; i < frames_.size(); ++i) {
        const Runs ran = runOn(i, cloudOnly(), true);
        EXPECT_EQ(ran, (Runs{{std::string(kPointCountStage), 1}})) << "frame " << i;
        EXPECT_FALSE(last_->pointColours || last_->cameraImage || last_->fog || last_->aura);
        EXPECT_FALSE(last_->automaticRange);
        EXPECT_GT(last_->pointCount, 0u);
    }
    // Each one runs as soon as something reads it, on the same frame.
    Demand d = cloudOnly();
    d.confidencePanel = true;
    EXPECT_EQ(runOn(1, d), (Runs{{std::string(processing::kConfidenceEstimateStage), 1},
                                 {std::string(kPointCountStage), 1}}));
    d.fog = true;
    EXPECT_EQ(runOn(1, d), (Runs{{std::string(kEffectsImageStage), 1}, {std::string(kFogStage), 1}}));
    EXPECT_TRUE(last_->fog);
    EXPECT_FALSE(last_->aura);
    // A panel that shows the depth already made asks for nothing new.
    d.depthImage = true;
    EXPECT_EQ(runOn(1, d), Runs{});
}

// A camera that sends MJPEG: the frame carries the JPEG, and only a stage that reads the camera's pixels
// has it decoded, once per frame, for every reader.
TEST_F(ProcessingGraphTest, ACameraJpegIsDecodedOnceAndOnlyWhenSomethingShowsTheCamera) {
    const frame::CapturedImage& nv12 = frames_[0]->capturedImage;
    frame::JpegEncoder encoder; // its result lives in the encoder
    const auto encoded = encoder.encode(nv12, 90);
    ASSERT_TRUE(encoded) << encoded.error().message;
    auto mjpeg = std::make_shared<frame::Frame>(*frames_[0]);
    mjpeg->capturedImage = {
        frame::PixelFormat::Jpeg, nv12.width, nv12.height,
        std::make_shared<const std::vector<std::uint8_t>>(encoded->begin(), encoded->end())};
    frames_[0] = mjpeg;
    const auto expected = frame::JpegDecoder().decode(mjpeg->capturedImage);
    ASSERT_TRUE(expected);

    EXPECT_EQ(runOn(0, cloudOnly(), true).count(kCameraDecodeStage), 0u);
    EXPECT_EQ(last_->frame, frames_[0]) << "nothing reads the camera: the frame is shown as captured";

    Demand camera = cloudOnly();
    camera.cameraPanelWidth = 320;
    const Runs ran = runOn(0, camera);
    EXPECT_EQ(ran.at(std::string(kCameraDecodeStage)), 1u);
    EXPECT_EQ(ran.at(std::string(kCameraImageStage)), 1u);
    const frame::CapturedImage& shownImage = last_->frame->capturedImage;
    EXPECT_EQ(shownImage.format, expected->format);
    EXPECT_EQ(*shownImage.bytes, *expected->bytes) << "every reader after sees the decoded pixels";

    const Runs more = runOn(0, everything());
    EXPECT_EQ(more.count(kCameraDecodeStage), 0u) << "decoded once per frame, whatever reads it next";
    ASSERT_TRUE(last_->pointColours);
    const processing::RgbImage colours =
        processing::pointColours(*expected, last_->depth.width(), last_->depth.height());
    EXPECT_EQ(last_->pointColours->pixels, colours.pixels);
}

TEST_F(ProcessingGraphTest, ANewFrameRerunsWhatItFeedsAndResetStartsOver) {
    runOn(0, everything(), true);
    const Runs next = runOn(1, everything(), true);
    EXPECT_EQ(next.size(), 10u) << "every stage reads the frame";
    // After a reset (a seek), the same frame and demand make everything again: nothing is remembered.
    graph_.reset();
    EXPECT_EQ(runOn(1, everything()).size(), 10u);
}

// The Quality panel's figures: measured once per frame and question, off while nobody asks, each new frame
// entering the noise window once, and a new region starting the window over.
TEST_F(ProcessingGraphTest, QualityIsMeasuredOncePerFrameAndRegionAndOnlyWhileAsked) {
    const std::string quality(kQualityStage);
    EXPECT_EQ(runOn(0, cloudOnly(), true).count(quality), 0u) << "nobody asked";
    EXPECT_FALSE(last_->quality);
    Demand d = cloudOnly();
    d.quality = QualityDemand{};
    EXPECT_EQ(runOn(0, d).at(quality), 1u);
    ASSERT_TRUE(last_->quality);
    EXPECT_EQ(last_->quality->roi, processing::centredRoi(last_->depth.width(), last_->depth.height(), 40.0));
    EXPECT_EQ(last_->quality->windowFilled, 1u);
    EXPECT_EQ(runOn(0, d).count(quality), 0u) << "the same frame and question are not measured again";
    EXPECT_EQ(runOn(1, d, true).at(quality), 1u);
    EXPECT_EQ(last_->quality->windowFilled, 2u);
    EXPECT_EQ(last_->quality->sequence, frames_[1]->sequence);
    // The causes' overlay asked for: the same frame measured again with it, without entering the window
    // twice.
    d.quality->causeOverlay = true;
    EXPECT_EQ(runOn(1, d).at(quality), 1u);
    ASSERT_TRUE(last_->quality->causeOverlay);
    const processing::RgbaImage& causes = *last_->quality->causeOverlay;
    EXPECT_EQ(causes.width, last_->quality->roi.width);
    EXPECT_EQ(causes.height, last_->quality->roi.height);
    std::size_t opaque = 0;
    for (std::size_t i = 3; i < causes.pixels.size(); i += 4)
        opaque += causes.pixels[i] == 255;
    const processing::FillBreakdown& fill = last_->quality->figures->fill;
    EXPECT_EQ(opaque, fill.roiSamples - fill.valid) << "one opaque pixel per missing sample";
    EXPECT_EQ(last_->quality->windowFilled, 2u) << "showing the causes does not start the window over";
    d.quality->causeOverlay = false;
    d.quality->roiPercent = 0;
    d.quality->roi = {250, 180, 40, 40}; // partly off the 256x192 map
    EXPECT_EQ(runOn(1, d).at(quality), 1u);
    EXPECT_EQ(last_->quality->roi, (processing::Roi{250, 180, 6, 12})) << "clamped to the map";
    EXPECT_EQ(last_->quality->windowFilled, 1u) << "another region starts the noise window over";
    d.quality->roi = {0, 0, 1, 1}; // too few samples for a plane: said, not thrown
    runOn(1, d);
    ASSERT_TRUE(last_->quality->figures);
    EXPECT_FALSE(last_->quality->figures->plane);
    EXPECT_FALSE(last_->quality->figures->planeError.empty());
}

// A polygon region: its bounding box measured (the vertices clamped to the 256x192 map first), the polygon
// echoed as measured, only the samples inside counted, and a new polygon starts the window over.
TEST_F(ProcessingGraphTest, APolygonDemandMeasuresItsInsideOverItsBoundingBox) {
    const std::string quality(kQualityStage);
    Demand d = cloudOnly();
    d.quality = QualityDemand{};
    d.quality->roiPercent = 0;
    d.quality->roi = {0, 0, 8, 8}; // ignored while there is a polygon
    d.quality->polygon = {{40.5, 30.0}, {120.0, 30.0}, {40.5, 100.25}};
    EXPECT_EQ(runOn(0, d).at(quality), 1u);
    ASSERT_TRUE(last_->quality && last_->quality->figures);
    EXPECT_EQ(last_->quality->roi, (processing::Roi{40, 30, 80, 71}));
    EXPECT_EQ(last_->quality->polygon, d.quality->polygon);
    std::size_t inside = 0;
    const processing::Roi& r = last_->quality->roi;
    for (int y = r.y; y < r.y + r.height; ++y)
        for (int x = r.x; x < r.x + r.width; ++x)
            inside += processing::insidePolygon(d.quality->polygon, x + 0.5, y + 0.5);
    EXPECT_LT(inside, static_cast<std::size_t>(r.width * r.height));
    EXPECT_EQ(last_->quality->figures->fill.roiSamples, inside);
    runOn(1, d, true);
    EXPECT_EQ(last_->quality->windowFilled, 2u);
    d.quality->polygon[2] = {300.0, 250.0}; // off the map: clamped to its corner
    EXPECT_EQ(runOn(1, d).at(quality), 1u);
    EXPECT_EQ(last_->quality->windowFilled, 1u) << "another polygon starts the noise window over";
    EXPECT_EQ(last_->quality->roi, (processing::Roi{40, 30, 216, 162}));
    EXPECT_EQ(last_->quality->polygon[2], (std::array<double, 2>{256.0, 192.0}));
}

} // namespace
} // namespace dc::engine::test

namespace dc::engine::test {
namespace {

// The first frame of the synthetic rig at a quarter of its sizes; null when the device cannot open.
frame::FramePtr smallRigFrame() {
    devices::SyntheticDevice device(dc::test::smallRigConfig());
    return device.open() ? device.makeFrame(0, 0.0) : nullptr;
}

// A two-sensor frame: the cloud is placed with the depth sensor's intrinsics, its points coloured where the
// colour sensor sees them, and the mask of those it cannot see travels with the colours.
TEST(ProcessingGraphRig, PointsOfATwoSensorFrameAreRegisteredAndCarryTheSeenMask) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);

    ProcessingGraph graph;
    Demand demand;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(shown->pointColours && shown->pointSeen);
    EXPECT_EQ(shown->depth.intrinsics, frame->rig->depth.intrinsics.scaledTo(212, 120));
    processing::CameraColourTable table;
    const processing::PointColours expected =
        processing::framePointColours(*frame, frame->sceneDepth->depthMeters, table);
    EXPECT_EQ(shown->pointColours->pixels, expected.colours->pixels);
    EXPECT_EQ(shown->pointSeen->pixels, expected.seen->pixels);
    // The depth sensor sees more than the colour sensor: its margins are unseen, its centre seen.
    EXPECT_EQ(shown->pointSeen->at(0, 60), 0);
    EXPECT_EQ(shown->pointSeen->at(106, 60), 1);
    EXPECT_NE(shown->pointColours->pixels, processing::pointColours(frame->capturedImage, 212, 120).pixels);
}

// Fog and aura of a two-sensor frame are made from the depth as the colour sensor sees it, aligned once at
// the effects' size and shared by both.
TEST(ProcessingGraphRig, FogAndAuraOfATwoSensorFrameUseTheDepthAlignedToTheColourImage) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);

    ProcessingGraph graph;
    Demand demand;
    demand.fog = true;
    demand.aura = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 1u);
    ASSERT_TRUE(shown->fog && shown->aura && shown->depth.data);

    const auto [w, h] = processing::halfCameraSize(frame->capturedImage);
    const processing::RgbImage camera = processing::cameraRgbImage(frame->capturedImage, w, h);
    frame::DepthData aligned;
    aligned.depthMeters = processing::alignDepthToColour(shown->depth.data->depthMeters, *frame->rig, w, h);
    const processing::RgbaImage fog = processing::renderFog(camera, &aligned, demand.processing.fog);
    EXPECT_EQ(shown->fog->pixels, fog.pixels);
    // The sensor-view depth would fog other pixels: the two sensors see the scene from different places.
    const processing::RgbaImage unaligned =
        processing::renderFog(camera, shown->depth.data.get(), demand.processing.fog);
    EXPECT_NE(shown->fog->pixels, unaligned.pixels);
    const processing::RgbaImage aura =
        processing::renderAura(camera, &aligned, frame->rig->colour.intrinsics.scaledTo(w, h),
                               demand.processing.aura, static_cast<double>(frame->timestampNs) * 1e-9);
    EXPECT_EQ(shown->aura->pixels, aura.pixels);

    // The same frame again aligns nothing again.
    graph.run(frame, demand, 2, false);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 1u);
}

// The camera panel's depth overlay of a two-sensor frame is the shown depth aligned to the colour image,
// holes (colour pixels no sample covers) included, made only while the overlay is shown and aligned once
// for it and fog together.
TEST(ProcessingGraphRig, DepthOverCameraIsTheAlignedDepthMadeOnlyWhileShown) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand;
    demand.cameraPanelWidth = 320;
    const processing::ShownFramePtr hidden = graph.run(frame, demand, 1, true);
    EXPECT_FALSE(hidden->depthOverCamera);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 0u) << "nothing aligned for an overlay that is off";

    demand.depthOverCamera = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 2, false);
    ASSERT_TRUE(shown->depthOverCamera && shown->depth.data);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 1u);
    const auto [w, h] = processing::halfCameraSize(frame->capturedImage);
    const frame::Plane<float> aligned =
        processing::alignDepthToColour(shown->depth.data->depthMeters, *frame->rig, w, h);
    const frame::Plane<float>& overlay = shown->depthOverCamera->depthMeters;
    ASSERT_EQ(overlay.width, w);
    ASSERT_EQ(overlay.height, h);
    EXPECT_EQ(overlay.pixels, aligned.pixels);
    const auto holes = std::count(overlay.pixels.begin(), overlay.pixels.end(), 0.0f);
    EXPECT_GT(holes, 0) << "the depth sensor's shadows leave colour pixels without depth";
    EXPECT_LT(holes, static_cast<long>(overlay.pixels.size()) / 2);

    demand.fog = true;
    graph.run(frame, demand, 3, false);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 1u) << "fog uses the overlay's aligned depth";
}

// A single camera's depth over the camera is the depth panel's image: nothing is aligned for it.
TEST(ProcessingGraphRig, DepthOverCameraOfASingleCameraAlignsNothing) {
    const frame::FramePtr frame = syntheticFrames(1).front();
    ASSERT_FALSE(frame->rig);
    ProcessingGraph graph;
    Demand demand;
    demand.cameraPanelWidth = 320;
    demand.depthOverCamera = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    EXPECT_FALSE(shown->depthOverCamera);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 0u);
}

// The depth panel's colour overlay is the registered colour of each depth sample, fully transparent exactly
// where the colour camera does not see the sample, and made only while shown.
TEST(ProcessingGraphRig, ColourOverDepthIsTheRegisteredColourAndTransparentWhereUnseen) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.depthImage = true;
    const processing::ShownFramePtr off = graph.run(frame, demand, 1, true);
    EXPECT_FALSE(off->colourOverDepth);
    EXPECT_EQ(graph.runs(kColourOverlayStage), 0u);
    EXPECT_EQ(graph.runs(kPointColoursStage), 0u) << "no colour is made for a cloud coloured by depth";

    demand.colourOverDepth = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 2, false);
    ASSERT_TRUE(shown->colourOverDepth && shown->depth.data);
    EXPECT_FALSE(shown->cloud.colours) << "the points do not take the camera's colour";
    EXPECT_EQ(graph.runs(kColourOverlayStage), 1u);
    processing::CameraColourTable table;
    const processing::PointColours expected =
        processing::framePointColours(*frame, shown->depth.data->depthMeters, table);
    ASSERT_TRUE(expected.seen);
    const processing::RgbaImage& overlay = *shown->colourOverDepth;
    ASSERT_EQ(overlay.width, shown->depth.width());
    ASSERT_EQ(overlay.height, shown->depth.height());
    std::size_t seen = 0, unseen = 0;
    for (std::size_t i = 0; i < expected.seen->pixels.size(); ++i) {
        const std::uint8_t* rgba = &overlay.pixels[i * 4];
        if (expected.seen->pixels[i] == 0) {
            ++unseen;
            ASSERT_EQ(rgba[3], 0) << "sample " << i << " is not seen by the colour camera";
            continue;
        }
        ++seen;
        ASSERT_EQ(rgba[3], 255) << "sample " << i;
        for (std::size_t c = 0; c < 3; ++c)
            ASSERT_EQ(rgba[c], expected.colours->pixels[i * 3 + c]) << "sample " << i << " channel " << c;
    }
    EXPECT_GT(seen, 0u);
    EXPECT_GT(unseen, 0u);
    // The colour sensor's narrower view: the depth map's centre is seen, its margins are not.
    EXPECT_EQ(overlay.pixels[(60 * 212 + 106) * 4 + 3], 255);
    EXPECT_EQ(overlay.pixels[(60 * 212 + 0) * 4 + 3], 0);

    graph.run(frame, demand, 3, false);
    EXPECT_EQ(graph.runs(kColourOverlayStage), 1u) << "the same frame again makes nothing again";
}

// With one camera the colour over depth is the camera image at the depth's size, opaque everywhere.
TEST(ProcessingGraphRig, ColourOverDepthOfASingleCameraIsTheCameraImageAtTheDepthsSize) {
    const frame::FramePtr frame = syntheticFrames(1).front();
    ProcessingGraph graph;
    Demand demand;
    demand.colourOverDepth = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(shown->colourOverDepth && shown->depth.data);
    const processing::RgbImage camera =
        processing::pointColours(frame->capturedImage, shown->depth.width(), shown->depth.height());
    const processing::RgbaImage& overlay = *shown->colourOverDepth;
    ASSERT_EQ(overlay.pixels.size(), camera.pixels.size() / 3 * 4);
    for (std::size_t i = 0; i < camera.pixels.size() / 3; ++i) {
        ASSERT_EQ(overlay.pixels[i * 4 + 3], 255) << "pixel " << i;
        for (std::size_t c = 0; c < 3; ++c)
            ASSERT_EQ(overlay.pixels[i * 4 + c], camera.pixels[i * 3 + c]) << "pixel " << i;
    }
}

// A single camera's fog is made from the shown depth itself, as before two sensors existed: nothing is
// aligned.
TEST(ProcessingGraphRig, FogOfASingleCameraFrameUsesTheShownDepthAndAlignsNothing) {
    const frame::FramePtr frame = syntheticFrames(1).front();
    ASSERT_FALSE(frame->rig);
    ProcessingGraph graph;
    Demand demand;
    demand.fog = true;
    demand.aura = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 0u);
    ASSERT_TRUE(shown->fog && shown->depth.data);
    const auto [w, h] = processing::halfCameraSize(frame->capturedImage);
    const processing::RgbImage camera = processing::cameraRgbImage(frame->capturedImage, w, h);
    EXPECT_EQ(shown->fog->pixels,
              processing::renderFog(camera, shown->depth.data.get(), demand.processing.fog).pixels);
}

// Points the GL path's shader colours get no colour from the CPU, and its camera panel no picture: nothing
// converts the camera image, for one camera or for a rig the shader registers; the GL thread reads the raw
// image of the frame.
TEST(ProcessingGraphShaderColours, NoColourIsMadeForPointsTheShaderColours) {
    for (const frame::FramePtr& frame : {syntheticFrames(1).front(), smallRigFrame()}) {
        ASSERT_TRUE(frame);
        ProcessingGraph graph;
        Demand demand = cloudOnly();
        demand.pointColours = true;
        demand.gpuCameraColours = true;
        demand.cameraPanelWidth = 320;
        const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
        ASSERT_TRUE(shown->cloud.depth.data);
        EXPECT_FALSE(shown->cloud.colours);
        EXPECT_FALSE(shown->pointColours);
        EXPECT_FALSE(shown->cameraImage) << "the GL path draws the camera panel from the planes too";
        EXPECT_EQ(graph.runs(kPointColoursStage), 0u);
        EXPECT_EQ(graph.runs(kCameraImageStage), 0u) << "no camera conversion on the CPU";
        EXPECT_TRUE(shown->frame->capturedImage.raw() && !shown->frame->capturedImage.empty());

        demand.gpuCameraColours = false; // the splat path
        const processing::ShownFramePtr cpu = graph.run(frame, demand, 2, false);
        EXPECT_TRUE(cpu->cloud.colours && cpu->cameraImage);
        EXPECT_EQ(graph.runs(kPointColoursStage), 1u);
        EXPECT_EQ(graph.runs(kCameraImageStage), 1u);
    }
}

// The GL path makes the depth panel's colour overlay and the depth over the camera in shaders too: with
// both shown, the engine colours no sample, makes no overlay image and aligns no depth. The splat path's
// engine makes both, and so does the GL path's for a rig the shaders cannot register.
TEST(ProcessingGraphShaderColours, TheGlPathsOverlaysAreNotMadeOnTheCpu) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.depthImage = true;
    demand.colourOverDepth = true;
    demand.depthOverCamera = true;
    demand.cameraPanelWidth = 320;
    demand.gpuCameraColours = true;
    const processing::ShownFramePtr gpu = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(gpu->depth.data);
    EXPECT_FALSE(gpu->colourOverDepth);
    EXPECT_FALSE(gpu->depthOverCamera);
    EXPECT_FALSE(gpu->pointColours);
    EXPECT_EQ(graph.runs(kColourOverlayStage), 0u);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 0u);
    EXPECT_EQ(graph.runs(kPointColoursStage), 0u);

    demand.gpuCameraColours = false; // the splat path
    const processing::ShownFramePtr cpu = graph.run(frame, demand, 2, false);
    EXPECT_TRUE(cpu->colourOverDepth && cpu->depthOverCamera);
    EXPECT_EQ(graph.runs(kColourOverlayStage), 1u);
    EXPECT_EQ(graph.runs(kAlignedDepthStage), 1u);

    auto inverseLens = std::make_shared<frame::RigCalibration>(*frame->rig);
    inverseLens->colour.lens.model = frame::LensModel::InverseBrownConrady;
    ASSERT_FALSE(processing::shaderCanColour(inverseLens.get()));
    auto other = std::make_shared<frame::Frame>(*frame);
    other->rig = inverseLens;
    demand.gpuCameraColours = true;
    const processing::ShownFramePtr unregistrable = graph.run(other, demand, 3, true);
    EXPECT_TRUE(unregistrable->colourOverDepth && unregistrable->depthOverCamera);
}

// A decimated cloud's colours are made for the samples it draws alone, where they are drawn (each cell's
// kept sample at the cell's centre), and none for the samples it leaves out.
TEST(ProcessingGraphShaderColours, ADecimatedCloudIsColouredOnlyWhereItsPointsAre) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.pointColours = true;
    demand.cloudDecimation = 2;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    const processing::ShownDepth& cloud = shown->cloud.depth;
    ASSERT_TRUE(cloud.data && shown->cloud.colours);
    EXPECT_EQ(cloud.width(), 106);
    EXPECT_FALSE(shown->pointColours) << "no colour for samples the cloud does not draw";
    processing::CameraColourTable table;
    const auto expected =
        processing::framePointColours(*frame, cloud.data->depthMeters, cloud.intrinsics, table).colours;
    EXPECT_EQ(shown->cloud.colours->pixels, expected->pixels);
    EXPECT_EQ(graph.runs(kPointColoursStage), 1u);
}

} // namespace
} // namespace dc::engine::test

namespace dc::engine::test {
namespace {

// The frame's colour registered onto the depth it was shown with, as the alignment scores it.
processing::RgbImage colourOnShownDepth(const frame::Frame& frame, const processing::ShownFrame& shown) {
    processing::CameraColourTable table;
    const frame::Plane<float>& depth = shown.depth.data->depthMeters;
    return processing::colourAlignedToDepth(frame, depth, depth.width, depth.height, table);
}

// The Quality panel's colour-to-depth alignment of a two-sensor frame: only when asked, equal to the colour
// registered onto the shown depth and scored here, and asking for it does not start the noise window over.
TEST(ProcessingGraphRig, TheColourAlignmentIsMeasuredOnTheShownDepthOnlyWhenAsked) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.quality = QualityDemand{};
    demand.quality->roiPercent = 80;
    const processing::ShownFramePtr off = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(off->quality);
    EXPECT_FALSE(off->quality->alignment);
    EXPECT_TRUE(off->quality->alignmentError.empty()) << "not asked, not measured";

    demand.quality->alignment = true;
    const processing::ShownFramePtr on = graph.run(frame, demand, 2, false);
    ASSERT_TRUE(on->quality && on->depth.data);
    ASSERT_TRUE(on->quality->alignment) << on->quality->alignmentError;
    const frame::Plane<float>& depth = on->depth.data->depthMeters;
    const auto expected = processing::measureEdgeAlignment(depth, colourOnShownDepth(*frame, *on),
                                                           on->depth.intrinsics, on->quality->roi);
    ASSERT_TRUE(expected.ok()) << expected.error().message;
    EXPECT_DOUBLE_EQ(on->quality->alignment->medianPx, expected->medianPx);
    EXPECT_DOUBLE_EQ(on->quality->alignment->medianMm, expected->medianMm);
    EXPECT_EQ(on->quality->alignment->matched, expected->matched);
    EXPECT_LT(on->quality->alignment->medianPx, 1.5) << "the synthetic rig is registered by construction";
    EXPECT_EQ(on->quality->windowFilled, 1u) << "the same frame again, the window not started over";
}

// A lasso's alignment scores the depth edges inside it, not those of its bounds.
TEST(ProcessingGraphRig, TheColourAlignmentOfALassoScoresOnlyItsSamples) {
    const frame::FramePtr frame = smallRigFrame();
    ASSERT_TRUE(frame && frame->rig);
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.quality = QualityDemand{};
    demand.quality->roiPercent = 0;
    demand.quality->alignment = true;
    const frame::Plane<float>& shown = frame->sceneDepth->depthMeters;
    const double w = shown.width, h = shown.height;
    demand.quality->polygon = {{0.05 * w, 0.05 * h}, {0.95 * w, 0.05 * h}, {0.05 * w, 0.95 * h}};
    const processing::ShownFramePtr on = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(on->quality && on->depth.data);
    ASSERT_TRUE(on->quality->alignment) << on->quality->alignmentError;
    ASSERT_EQ(on->quality->polygon.size(), 3u);
    const frame::Plane<float>& depth = on->depth.data->depthMeters;
    const processing::RgbImage colour = colourOnShownDepth(*frame, *on);
    const auto inLasso = processing::measureEdgeAlignment(depth, colour, on->depth.intrinsics,
                                                          on->quality->roi, on->quality->polygon);
    const auto inBounds =
        processing::measureEdgeAlignment(depth, colour, on->depth.intrinsics, on->quality->roi);
    ASSERT_TRUE(inLasso.ok() && inBounds.ok());
    EXPECT_EQ(on->quality->alignment->depthEdgePixels, inLasso->depthEdgePixels);
    EXPECT_DOUBLE_EQ(on->quality->alignment->meanPx, inLasso->meanPx);
    EXPECT_LT(inLasso->depthEdgePixels, inBounds->depthEdgePixels)
        << "the bounds hold edges the lasso does not";
}

// A frame without a camera image says so rather than scoring nothing.
TEST(ProcessingGraphRig, WithoutACameraImageTheAlignmentSaysWhy) {
    auto frame = std::make_shared<frame::Frame>(*smallRigFrame());
    frame->capturedImage = frame::CapturedImage{};
    ProcessingGraph graph;
    Demand demand = cloudOnly();
    demand.pointColours = false;
    demand.quality = QualityDemand{};
    demand.quality->alignment = true;
    const processing::ShownFramePtr shown = graph.run(frame, demand, 1, true);
    ASSERT_TRUE(shown->quality);
    EXPECT_FALSE(shown->quality->alignment);
    EXPECT_EQ(shown->quality->alignmentError, "the frame has no camera image");
}

} // namespace
} // namespace dc::engine::test
