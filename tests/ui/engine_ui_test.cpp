// The engine seen from the UI: a settings change is shown at once whatever the source is doing, nothing is
// computed or decoded for a panel nobody shows, and every reader of the cloud sees the same depth.

#include "devices/frame_list_device.h"
#include "devices/replay/replay_device.h"
#include "devices/replay/replay_source.h"
#include "devices/source_spec.h"
#include "engine/processing_graph.h"
#include "failing_camera.h"
#include "processing/camera_image.h"
#include "processing/confidence_filter.h"
#include "processing/infrared_image.h"
#include "processing/point_cloud.h"
#include "processing/registration.h"
#include "tests/small_rig.h"
#include "tests/test_data.h"
#include "ui_fixture.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <thread>
#include <unistd.h>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

struct PlyPoint {
    float x, y, z;
    std::uint8_t r, g, b, confidence;
};

// Our binary PLY (exporting/ply.cpp): a text header, then x y z as float and r g b confidence as bytes.
std::vector<PlyPoint> readPly(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), {}};
    const std::size_t body = bytes.find("end_header\n") + 11;
    std::vector<PlyPoint> points((bytes.size() - body) / 16);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const char* p = bytes.data() + body + i * 16;
        std::memcpy(&points[i].x, p, 12);
        std::memcpy(&points[i].r, p + 12, 4);
    }
    return points;
}

// The points the cloud's vertex shader draws, from what it reads: the depth, confidence and colour
// textures on the GPU and the depth intrinsics it is given.
std::vector<PlyPoint> drawnPoints(const render::FrameTextures& t, frame::Confidence minLevel, float near) {
    const int w = t.depthWidth(), h = t.depthHeight();
    const auto n = static_cast<std::size_t>(w) * h;
    std::vector<float> depth(n);
    std::vector<std::uint8_t> confidence(n), rgb(n * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindTexture(GL_TEXTURE_2D, t.depthTexture());
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, depth.data());
    glBindTexture(GL_TEXTURE_2D, t.confidenceTexture());
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, confidence.data());
    glBindTexture(GL_TEXTURE_2D, t.colorTexture());
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    std::vector<PlyPoint> points;
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * w + u;
            if (!processing::keepSample(depth[i], confidence[i], minLevel, near))
                continue;
            const auto [x, y, z] = processing::unproject(u, v, depth[i], t.depthIntrinsics());
            points.push_back({x, y, z, rgb[i * 3], rgb[i * 3 + 1], rgb[i * 3 + 2], confidence[i]});
        }
    }
    return points;
}

class EngineUiTest : public UiTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(initGl());
        ASSERT_NO_FATAL_FAILURE(startViewer(smallScene()));
        dir_ = fs::temp_directory_path() / ("dc-engine-ui-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }

    void TearDown() override {
        UiTest::TearDown();
        fs::remove_all(dir_);
    }

    // A paused replay of a few synthetic frames recorded through the real recorder.
    void startPausedReplay() {
        const std::string path = (dir_ / "scene.dcrec").string();
        ASSERT_TRUE(instrument_->startRecording(path).ok());
        for (int i = 0; i < 400 && instrument_->recording().frames < 6; ++i)
            nextFrame(0.0);
        ASSERT_TRUE(instrument_->stopRecording().ok());
        ASSERT_TRUE(viewer_->openSource("replay:" + path + ":paused").ok());
        viewer_->settings().cloud.motion.enabled = false;
        ASSERT_TRUE(nextFrame(0.0));
        viewer_->setRedoWait(std::chrono::seconds(10));
    }

    std::uint64_t shownSequence() const { return shown().frame->sequence; }

    // One frame as the window draws it: only if its picture changes. Returns whether it was drawn.
    bool windowFrame() {
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(0.0);
        viewer_->drawUi();
        const bool drawn = gui_.renderIfChanged(renderer_.contentVersion());
        viewer_->presented(drawn);
        return drawn;
    }

    // Whether the picture the window holds is the one a full redraw of the same frame draws.
    bool keptPictureIsCurrent() {
        const std::vector<std::uint8_t> kept = gui_.target().readRgba();
        frame(0.0);
        return gui_.target().readRgba() == kept;
    }

    // Window frames until none was drawn for longer than the figures' refresh interval.
    bool settle() {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        auto lastDrawn = std::chrono::steady_clock::now();
        while (std::chrono::steady_clock::now() - lastDrawn < Viewer::kMeasureInterval + kQuiet) {
            if (std::chrono::steady_clock::now() > deadline)
                return false;
            if (windowFrame())
                lastDrawn = std::chrono::steady_clock::now();
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return true;
    }
    static constexpr std::chrono::milliseconds kQuiet{200};

    fs::path dir_;
};

// Everything the issue lists, one change at a time, each checked in the very next drawn frame.
void expectEachSettingShowsInTheNextFrame(UiTest& t, Viewer& viewer, const render::ViewRenderer& renderer,
                                          const std::function<void()>& frame) {
    const auto sequence = viewer.shown()->frame->sequence;
    Settings& s = viewer.settings();

    const auto depthBefore = renderer.depthTarget().readRgba();
    const std::uint64_t panelRenders = renderer.panelRenders();
    s.depthRange.colormap = render::Colormap::Viridis;
    frame();
    EXPECT_GT(renderer.panelRenders(), panelRenders) << "the panels are drawn again";
    EXPECT_EQ(viewer.depthLegend().colormap, render::Colormap::Viridis);
    EXPECT_NE(renderer.depthTarget().readRgba(), depthBefore) << "the depth panel is redrawn in viridis";

    const std::uint64_t rawPoints = viewer.statusLine().pointsDrawn;
    s.processing.upsampling = true;
    frame();
    EXPECT_TRUE(viewer.shown()->depth.upsampled);
    EXPECT_EQ(viewer.shown()->depth.width(), 320) << "half the 640x480 camera image";
    EXPECT_GT(viewer.statusLine().pointsDrawn, rawPoints * 3 / 2)
        << "320x240 points where there were 256x192";
    EXPECT_EQ(viewer.statusLine().pointsDrawn, viewer.shown()->pointCount);

    s.processing.upsampling = false;
    s.processing.smoothing = true;
    s.processing.depthSource = processing::DepthSource::Smoothed;
    frame();
    EXPECT_TRUE(viewer.shown()->depth.smoothed);
    EXPECT_EQ(viewer.statusLine().pointsDrawn, viewer.shown()->pointCount);

    s.processing.depthSource = processing::DepthSource::Raw;
    frame();
    EXPECT_FALSE(viewer.shown()->depth.smoothed);

    s.panels.fog = true;
    frame();
    EXPECT_GT(renderer.fogTexture().width(), 0) << "the fog panel has its image at once";
    EXPECT_EQ(viewer.shown()->frame->sequence, sequence) << "all of it without a new device frame";
    (void)t;
}

TEST_F(EngineUiTest, APausedReplayShowsEverySettingChangeInTheNextFrame) {
    ASSERT_NO_FATAL_FAILURE(startPausedReplay());
    ASSERT_FALSE(instrument_->replay()->status().playing);
    expectEachSettingShowsInTheNextFrame(*this, *viewer_, renderer_, [this] { frame(0.0); });
}

// The status line says where a replay stands from the instrument's typed state: paused, then playing
// (the device's own state), then at its end.
TEST_F(EngineUiTest, TheStatusLineSaysAReplayIsPausedPlayingOrEnded) {
    ASSERT_NO_FATAL_FAILURE(startPausedReplay());
    EXPECT_EQ(instrument_->status().state.note, engine::SourceState::Note::Paused);
    EXPECT_EQ(viewer_->statusLine().state, "paused");
    instrument_->replay()->setLoop(false);
    instrument_->replay()->play();
    EXPECT_EQ(viewer_->statusLine().state, "streaming");
    for (int i = 0; i < 400 && !instrument_->replay()->status().atEnd; ++i)
        frame(0.0);
    ASSERT_TRUE(instrument_->replay()->status().atEnd);
    EXPECT_EQ(instrument_->status().state.note, engine::SourceState::Note::Ended);
    EXPECT_EQ(viewer_->statusLine().state, "ended");
}

// Nothing is computed for nobody, down to the composite: a still, paused view is not drawn again, and
// each change to it is drawn in the very next frame, also one that only a texture shows (the cloud turned).
TEST_F(EngineUiTest, AStillViewKeepsItsPictureAndEveryChangeIsDrawnInTheNextFrame) {
    ASSERT_NO_FATAL_FAILURE(startPausedReplay());
    ASSERT_TRUE(settle()) << "a paused view with nothing moving stops drawing";
    for (int i = 0; i < 30; ++i)
        ASSERT_FALSE(windowFrame()) << i;
    EXPECT_TRUE(keptPictureIsCurrent());
    EXPECT_GT(viewer_->summary().uiFramesKept, 30u);

    ASSERT_TRUE(settle());
    viewer_->settings().cloud.orbit.yawRadians += 0.3f; // as a drag would: only the cloud's texture changes
    EXPECT_TRUE(windowFrame()) << "the turned cloud";
    EXPECT_TRUE(keptPictureIsCurrent());

    ASSERT_TRUE(settle());
    viewer_->settings().depthRange.colormap = render::Colormap::Viridis;
    EXPECT_TRUE(windowFrame()) << "the depth panel in another colormap";
    EXPECT_TRUE(keptPictureIsCurrent());

    ASSERT_TRUE(settle());
    const ImGuiWindow* depth = ImGui::FindWindowByName(kDepthTitle);
    ASSERT_NE(depth, nullptr);
    gui_.io().MousePos = {depth->Pos.x + depth->Size.x * 0.5f, depth->Pos.y + depth->Size.y * 0.4f};
    // ImGui draws the readout in the frame after the one that finds the mouse over the panel.
    const bool first = windowFrame();
    const bool second = windowFrame();
    EXPECT_TRUE(first || second) << "the hover readout over the depth panel";
    EXPECT_TRUE(viewer_->hoverProbe().has_value());
    EXPECT_TRUE(keptPictureIsCurrent());
}

TEST_F(EngineUiTest, AStalledCameraShowsEverySettingChangeInTheNextFrame) {
    const auto last = std::make_shared<std::atomic<std::int64_t>>(-1);
    start(std::make_unique<FailingCamera>(2, devices::CaptureResult::Kind::Stalled,
                                          "stalling camera: no frame", last),
          "stalling");
    viewer_->settings().cloud.motion.enabled = false;
    // Until the camera has stalled with its last frame on screen (the second of its two frames may replace
    // the first before processing). Bounded in time: a sanitized build takes many more window frames.
    ASSERT_TRUE(frameUntil([&] {
        return viewer_->statusLine().state == "stalled" && viewer_->shown() &&
               static_cast<std::int64_t>(viewer_->shown()->frame->sequence) == last->load();
    })) << viewer_->statusLine().state
        << ", " << viewer_->statusLine().frames.shown << " shown";
    viewer_->setRedoWait(std::chrono::seconds(10));
    expectEachSettingShowsInTheNextFrame(*this, *viewer_, renderer_, [this] { frame(0.0); });
}

TEST_F(EngineUiTest, TheConfidenceEstimateRunsOnlyWhileSomethingReadsConfidence) {
    // A depth camera without confidence: the estimate is the only source of it.
    devices::SyntheticConfig config = smallScene();
    auto frames = std::vector<frame::FramePtr>();
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    for (int i = 0; i < 4; ++i) {
        auto f =
            std::make_shared<frame::Frame>(*device.makeFrame(static_cast<std::uint64_t>(i), i / config.fps));
        f->sceneDepth->confidence = {};
        frames.push_back(f);
    }
    Settings settings;
    settings.panels.confidence = false;
    start(std::make_unique<devices::FrameListDevice>(frames, 120.0), "no confidence", settings);
    for (int i = 0; i < 10; ++i)
        nextFrame(0.0);
    const engine::FrameProcessor& processor = instrument_->processor();
    EXPECT_EQ(processor.stageRuns("confidence estimate"), 0u) << "nothing reads confidence";
    viewer_->settings().cloud.minConfidence = frame::Confidence::Medium;
    for (int i = 0; i < 4; ++i)
        nextFrame(0.0);
    EXPECT_GT(processor.stageRuns("confidence estimate"), 0u) << "the level above all reads it";
    EXPECT_TRUE(shown().depth.data->confidenceEstimated);
}

TEST_F(EngineUiTest, WithSmoothingOrUpsamplingTheSnapshotHoldsExactlyThePointsDrawn) {
    viewer_->settings().cloud.motion.enabled = false;
    viewer_->settings().cloud.minConfidence = frame::Confidence::Medium;
    for (const bool upsampling : {false, true}) {
        viewer_->settings().processing.smoothing = !upsampling;
        viewer_->settings().processing.upsampling = upsampling;
        for (int i = 0; i < 3; ++i)
            nextFrame(0.0);
        ASSERT_EQ(shown().depth.upsampled, upsampling);
        ASSERT_EQ(shown().depth.smoothed, !upsampling);
        const auto dir = viewer_->saveSnapshot((dir_ / (upsampling ? "up" : "smooth")).string());
        ASSERT_TRUE(dir.ok()) << dir.error().message;
        const std::vector<PlyPoint> ply = readPly(fs::path(*dir) / "cloud.ply");
        const std::vector<PlyPoint> drawn = drawnPoints(renderer_.textures(), frame::Confidence::Medium,
                                                        viewer_->settings().cloud.nearMeters);
        ASSERT_EQ(ply.size(), drawn.size()) << (upsampling ? "upsampling" : "smoothing");
        ASSERT_EQ(ply.size(), shown().pointCount);
        for (std::size_t i = 0; i < ply.size(); ++i) {
            ASSERT_NEAR(ply[i].x, drawn[i].x, 1e-6f) << i;
            ASSERT_NEAR(ply[i].y, drawn[i].y, 1e-6f) << i;
            ASSERT_NEAR(ply[i].z, drawn[i].z, 1e-6f) << i;
            ASSERT_EQ(ply[i].r, drawn[i].r) << i;
            ASSERT_EQ(ply[i].confidence, drawn[i].confidence) << i;
        }
    }
}

// On the GL points path the overlays are made from the camera's planes on the GPU as well: with the colour
// overlay and the depth over the camera shown for a two-sensor frame, the engine neither colours the
// samples, nor makes the overlay image, nor aligns the depth to the colour image; the renderer draws both
// overlays, again for every new frame, at the sizes their panels show them.
TEST_F(EngineUiTest, OnTheGlPointsPathTheOverlaysAreMadeOnlyOnTheGpu) {
    devices::SyntheticConfig rig = dc::test::smallRigConfig();
    rig.noise = false;
    Settings settings;
    settings.cloud.path = CloudPathChoice::Points;
    settings.cloud.motion.enabled = false;
    settings.panels.camera = true;
    settings.panels.depth = true;
    settings.depthView.colourOverlay = true;
    settings.camera.depthOverlay = true;
    ASSERT_NO_FATAL_FAILURE(startViewer(rig, settings));
    ASSERT_TRUE(viewer_->demand().gpuCameraColours && viewer_->demand().colourOverDepth &&
                viewer_->demand().depthOverCamera);
    ASSERT_TRUE(frameUntil(
        [&] { return renderer_.colourOverDepthFromGpu() && renderer_.cameraColours().alignedPasses() > 0; }));
    const engine::FrameProcessor& processor = instrument_->processor();
    const std::uint64_t colourRuns = processor.stageRuns(engine::kPointColoursStage);
    const std::uint64_t seenPasses = renderer_.cameraColours().seenPasses();
    const std::uint64_t alignedPasses = renderer_.cameraColours().alignedPasses();
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(nextFrame(0.0));
    EXPECT_EQ(processor.stageRuns(engine::kColourOverlayStage), 0u) << "no colour overlay on the CPU";
    EXPECT_EQ(processor.stageRuns(engine::kAlignedDepthStage), 0u) << "no aligned depth on the CPU";
    EXPECT_EQ(processor.stageRuns(engine::kPointColoursStage), colourRuns) << "no sample colours on the CPU";
    EXPECT_FALSE(shown().colourOverDepth);
    EXPECT_FALSE(shown().depthOverCamera);
    EXPECT_GE(renderer_.cameraColours().seenPasses(), seenPasses + 3) << "each new frame's colour overlay";
    EXPECT_GE(renderer_.cameraColours().alignedPasses(), alignedPasses + 3) << "each new frame's depth";
    EXPECT_TRUE(renderer_.colourOverDepthFromGpu());
    EXPECT_TRUE(renderer_.alignsDepthOverCamera(true));
    EXPECT_EQ(renderer_.colourOverDepthTarget().width(), renderer_.depthTarget().width());
    EXPECT_EQ(renderer_.colourOverDepthTarget().height(), renderer_.depthTarget().height());
    const auto [w, h] =
        processing::cameraPanelImageSize(shown().frame->capturedImage, viewer_->demand().cameraPanelWidth);
    EXPECT_EQ(renderer_.depthOverCameraTarget().width(), w);
    EXPECT_EQ(renderer_.depthOverCameraTarget().height(), h);
}

// On the GL points path the GPU makes the camera's colours: the engine converts no camera image, the camera
// panel shows the picture drawn from the planes at the panel's size, and the snapshot PLY still carries the
// camera colours of the points, made for it on the CPU.
TEST_F(EngineUiTest, OnTheGlPointsPathTheCameraIsConvertedOnlyOnTheGpu) {
    viewer_->settings().cloud.motion.enabled = false;
    viewer_->settings().cloud.path = CloudPathChoice::Points;
    viewer_->settings().panels.camera = true;
    ASSERT_TRUE(frameUntil([&] { return renderer_.cameraFromGpu() && !shown().cameraImage; }));
    // Counted from here: the frames before the switch were drawn on the splat path.
    const engine::FrameProcessor& processor = instrument_->processor();
    const std::uint64_t colourRuns = processor.stageRuns(engine::kPointColoursStage);
    const std::uint64_t conversions = processor.stageRuns(engine::kCameraImageStage);
    for (int i = 0; i < 3; ++i)
        nextFrame(0.0);
    EXPECT_EQ(processor.stageRuns(engine::kPointColoursStage), colourRuns) << "no point colour on the CPU";
    EXPECT_EQ(processor.stageRuns(engine::kCameraImageStage), conversions)
        << "no camera conversion on the CPU";
    EXPECT_GT(renderer_.cameraColours().imagePasses(), 0u);
    const frame::CapturedImage& image = shown().frame->capturedImage;
    const auto [w, h] = processing::cameraPanelImageSize(image, viewer_->demand().cameraPanelWidth);
    EXPECT_EQ(renderer_.cameraTarget().width(), w);
    EXPECT_EQ(renderer_.cameraTarget().height(), h);

    const auto dir = viewer_->saveSnapshot((dir_ / "gpu").string());
    ASSERT_TRUE(dir.ok()) << dir.error().message;
    const std::vector<PlyPoint> ply = readPly(fs::path(*dir) / "cloud.ply");
    processing::CameraColourTable table;
    const processing::ShownDepth& depth = shown().depth;
    const auto colours =
        processing::framePointColours(*shown().frame, depth.data->depthMeters, table).colours;
    const auto expected = processing::buildPointCloud({depth.data.get(), depth.intrinsics, colours.get()},
                                                      viewer_->settings().cloud.minConfidence,
                                                      viewer_->settings().cloud.nearMeters);
    ASSERT_EQ(ply.size(), expected.size());
    ASSERT_FALSE(ply.empty());
    for (std::size_t i = 0; i < ply.size(); i += 97)
        ASSERT_TRUE(ply[i].r == expected[i].r && ply[i].g == expected[i].g && ply[i].b == expected[i].b) << i;
}

TEST_F(EngineUiTest, AccumulationAddsTheSamePointsTheSnapshotHolds) {
    // One posed frame of the moving scene, delivered again and again: the accumulator holds that frame's
    // shown points (later deliveries land in voxels already held), in the order the snapshot lists them.
    devices::SyntheticConfig moving = smallScene();
    moving.motion = true;
    devices::SyntheticDevice scene(moving);
    ASSERT_TRUE(scene.open().ok());
    const frame::FramePtr posed = scene.makeFrame(0, 0.7);
    ASSERT_TRUE(posed->pose.has_value());
    Settings settings;
    settings.cloud.motion.enabled = false;
    settings.processing.upsampling = true; // so the shown depth is not the sensor's
    settings.accumulate = {true, 1000, 0.5f};
    start(std::make_unique<devices::FrameListDevice>(std::vector<frame::FramePtr>{posed}, 30.0), "posed",
          settings);
    for (int i = 0; i < 4; ++i)
        ASSERT_TRUE(nextFrame(0.0));
    instrument_->accumulation().waitIdle();
    ASSERT_TRUE(shown().depth.upsampled);
    const auto dir = viewer_->saveSnapshot((dir_ / "acc").string());
    ASSERT_TRUE(dir.ok()) << dir.error().message;
    const std::vector<PlyPoint> ply = readPly(fs::path(*dir) / "cloud.ply");
    // Frames keep coming and the worker may be adding one (which adds nothing new): read between two. Under
    // a sanitizer and load an add can take longer than a frame's interval, so wait for an idle moment first.
    std::vector<processing::WorldPoint> world;
    bool wasRead = false;
    const auto read = [&](processing::PointAccumulator& points) {
        world.assign(points.slots().begin(),
                     points.slots().begin() + static_cast<std::ptrdiff_t>(points.size()));
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!wasRead && std::chrono::steady_clock::now() < deadline) {
        instrument_->accumulation().waitIdle();
        wasRead = instrument_->accumulation().tryRead(read);
    }
    ASSERT_TRUE(wasRead) << "the accumulation worker was never idle for a minute";
    // At a 0.5 mm voxel the desk's points, millimetres apart, each keep their own voxel.
    ASSERT_EQ(world.size(), ply.size());
    const auto& m = posed->pose->cameraToWorld; // column-major
    for (std::size_t i = 0; i < ply.size(); ++i) {
        const double x = ply[i].x, y = ply[i].y, z = ply[i].z;
        ASSERT_NEAR(world[i].x, m[0] * x + m[4] * y + m[8] * z + m[12], 1e-5) << i;
        ASSERT_NEAR(world[i].y, m[1] * x + m[5] * y + m[9] * z + m[13], 1e-5) << i;
        ASSERT_NEAR(world[i].z, m[2] * x + m[6] * y + m[10] * z + m[14], 1e-5) << i;
        const std::uint32_t rgb = ply[i].r | ply[i].g << 8 | ply[i].b << 16;
        ASSERT_EQ(world[i].rgba & 0xffffffu, rgb) << i;
    }
}

// The ARKit capture replayed as a user would, with the camera panel hidden and the points coloured by
// depth: its video is not decoded at all; showing the panel brings exactly that frame's image.
TEST_F(EngineUiTest, AReplayDecodesItsVideoOnlyWhileSomethingShowsIt) {
    Settings settings;
    settings.panels.camera = false;
    settings.cloud.coloring = render::PointColoring::Depth;
    settings.cloud.motion.enabled = false;
    auto device = devices::openSourceSpec("replay:" + dc::test::dataPath("arkit_dance_stray") + ":paused");
    ASSERT_TRUE(device.ok()) << device.error().message;
    start(std::move(*device), "replay", settings);
    viewer_->setRedoWait(std::chrono::seconds(10));
    ASSERT_TRUE(nextFrame(0.0));
    for (int i = 1; i <= 5; ++i) {
        instrument_->seekReplay(static_cast<std::size_t>(10 * i));
        ASSERT_TRUE(nextFrame(0.0));
    }
    EXPECT_EQ(shown().frame->replay->index, 50u);
    EXPECT_EQ(instrument_->replay()->status().colorDecodes, 0u) << "no panel and no point needs the video";
    EXPECT_EQ(shown().cameraImage, nullptr);

    viewer_->settings().panels.camera = true;
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown()->cameraImage != nullptr; }))
        << "the camera panel gets its image";
    EXPECT_EQ(shown().frame->replay->index, 50u) << "the same frame, now with its image";
    EXPECT_EQ(instrument_->replay()->status().colorDecodes, 1u);
    // The image is exactly frame 50's, decoded on its own by a second reader.
    auto source = devices::replay::openReplaySource(dc::test::dataPath("arkit_dance_stray"));
    ASSERT_TRUE(source.ok());
    auto reference = devices::replay::loadFrame(**source, 50);
    ASSERT_TRUE(reference.ok());
    const processing::RgbImage& image = *shown().cameraImage;
    EXPECT_EQ(processing::cameraRgbImage(reference->capturedImage, image.width, image.height).pixels,
              image.pixels);
}

// A 1024x768 map in a side panel a third as wide: the panels are drawn from every n-th sample, the ones
// nearest sampling shows, and a snapshot still writes every sample.
TEST_F(EngineUiTest, PanelsShownSmallerThanTheirMapDrawEveryNthSampleAndASnapshotWritesThemWhole) {
    devices::SyntheticConfig config = smallScene();
    config.depthWidth = 1024;
    config.depthHeight = 768;
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    const auto f = std::make_shared<frame::Frame>(*device.makeFrame(0, 0.0));
    Settings settings;
    settings.cloud.motion.enabled = false;
    start(std::make_unique<devices::FrameListDevice>(std::vector<frame::FramePtr>{f}, 60.0), "large depth",
          settings);
    viewer_->setRedoWait(std::chrono::seconds(10));
    for (int i = 0; i < 4; ++i)
        ASSERT_TRUE(nextFrame(0.0));
    const int width = shown().depth.width(), height = shown().depth.height();
    ASSERT_EQ(width, 1024);
    const render::RenderTarget& depth = renderer_.depthTarget();
    const render::RenderTarget& confidence = renderer_.confidenceTarget();
    const int step = (width + depth.width() - 1) / depth.width();
    ASSERT_GE(step, 2) << "drawn " << depth.width() << " wide";
    EXPECT_EQ(depth.width(), (width + step - 1) / step);
    EXPECT_EQ(confidence.width(), depth.width());
    ASSERT_NE(shown().panelSamples, nullptr) << "the engine picks the samples, told the panel's width";
    EXPECT_EQ(shown().panelStep, step);
    const std::vector<std::uint8_t> smallDepth = depth.readRgba(), smallConfidence = confidence.readRgba();
    const int smallWidth = depth.width(), smallHeight = depth.height();

    const auto written = viewer_->savePanels(dir_.string());
    ASSERT_TRUE(written.ok()) << written.error().message;
    ASSERT_EQ(depth.width(), width) << "the snapshot's depth.png holds every sample";
    ASSERT_EQ(depth.height(), height);
    const std::vector<std::uint8_t> wholeDepth = depth.readRgba(), wholeConfidence = confidence.readRgba();
    std::size_t differing = 0;
    for (int y = 0; y < smallHeight; ++y)
        for (int x = 0; x < smallWidth; ++x) {
            const std::size_t s = (static_cast<std::size_t>(y) * smallWidth + x) * 4;
            const std::size_t w =
                (static_cast<std::size_t>(std::min(height - 1, y * step + step / 2)) * width +
                 std::min(width - 1, x * step + step / 2)) *
                4;
            differing += !std::equal(&smallDepth[s], &smallDepth[s] + 4, &wholeDepth[w]) ||
                         !std::equal(&smallConfidence[s], &smallConfidence[s] + 4, &wholeConfidence[w]);
        }
    EXPECT_EQ(differing, 0u) << "each drawn pixel is its cell's centre sample";

    frame(0.0);
    EXPECT_EQ(depth.width(), smallWidth) << "shown again at the panel's size";
}

TEST_F(EngineUiTest, TheInfraredPanelsImageIsMadeOnlyWhileThePanelIsShown) {
    devices::SyntheticDevice device(smallScene());
    ASSERT_TRUE(device.open());
    auto f = std::make_shared<frame::Frame>(*device.makeFrame(0, 0.0));
    frame::Plane<std::uint16_t> infrared(32, 24);
    for (std::size_t i = 0; i < infrared.pixels.size(); ++i)
        infrared.pixels[i] = static_cast<std::uint16_t>(i * 37 % 1000);
    f->infrared = infrared;
    Settings settings;
    settings.cloud.motion.enabled = false;
    start(std::make_unique<devices::FrameListDevice>(std::vector<frame::FramePtr>{f}, 60.0), "infrared",
          settings);
    viewer_->setRedoWait(std::chrono::seconds(10));
    for (int i = 0; i < 4; ++i)
        nextFrame(0.0);
    const engine::FrameProcessor& processor = instrument_->processor();
    EXPECT_EQ(processor.stageRuns(engine::kInfraredImageStage), 0u) << "the panel is off by default";
    EXPECT_EQ(shown().infraredImage, nullptr);
    EXPECT_EQ(ImGui::FindWindowByName(kInfraredTitle), nullptr);

    viewer_->settings().panels.infrared = true;
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown()->infraredImage != nullptr; }));
    frame(0.0);
    const processing::RgbImage& image = *shown().infraredImage;
    EXPECT_EQ(image.pixels,
              processing::infraredRgbImage(infrared, processing::infraredContrastRange(infrared)).pixels);
    EXPECT_EQ(renderer_.infraredTexture().width(), 32);
    EXPECT_EQ(renderer_.infraredTexture().height(), 24);
    EXPECT_NE(ImGui::FindWindowByName(kInfraredTitle), nullptr) << "the panel is drawn";
    EXPECT_GT(processor.stageRuns(engine::kInfraredImageStage), 0u);
    EXPECT_EQ(shown().infraredRange, processing::infraredContrastRange(infrared)) << "the legend's stretch";
    // The readout gives the raw intensity under the mouse; the infrared is a quarter of the depth's size.
    const frame::DepthData& depth = *shown().depth.data;
    const int u = depth.depthMeters.width * 3 / 4, v = depth.depthMeters.height / 2;
    const std::optional<Probe> probe = probeAt(viewer_->probeSource(), u, v);
    ASSERT_TRUE(probe && probe->infrared);
    EXPECT_EQ(*probe->infrared,
              infrared.at(u * 32 / depth.depthMeters.width, v * 24 / depth.depthMeters.height));

    viewer_->settings().panels.infrared = false;
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown()->infraredImage == nullptr; }))
        << "hidden again, the engine makes no infrared image";
    const std::uint64_t runs = processor.stageRuns(engine::kInfraredImageStage);
    for (int i = 0; i < 4; ++i)
        nextFrame(0.0);
    EXPECT_EQ(processor.stageRuns(engine::kInfraredImageStage), runs);
}

TEST_F(EngineUiTest, TheInfraredPanelIsNotDrawnForASourceWithoutInfrared) {
    viewer_->settings().panels.infrared = true;
    for (int i = 0; i < 4; ++i)
        nextFrame(0.0);
    EXPECT_FALSE(shown().frame->infrared);
    EXPECT_EQ(shown().infraredImage, nullptr);
    EXPECT_EQ(ImGui::FindWindowByName(kInfraredTitle), nullptr) << "no panel for what the source lacks";
}

} // namespace
} // namespace dc::ui::test
