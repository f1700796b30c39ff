// Headless UI tests of the viewer's core controls: confidence, rotation, orbit, zoom, shortcuts, stages.

#include "failing_camera.h"
#include "ui_fixture.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <thread>

namespace dc::ui::test {
namespace {

TEST_F(UiTest, EveryPanelSurvivesHundredsOfFramesBeingShownAndHidden) {
    PanelVisibility& show = viewer_->settings().panels;
    for (int i = 0; i < 300; ++i) {
        show.cloud = i % 50 < 40;
        show.depth = i % 30 < 20;
        show.confidence = i % 70 < 50;
        show.camera = i % 20 < 15;
        show.controls = i % 90 < 80;
        show.stats = i % 40 < 25;
        show.log = i % 60 < 45;
        show.source = i % 45 < 30;
        show.fog = i % 55 < 35;
        show.aura = i % 65 < 40;
        show.quality = i % 35 < 20;
        static constexpr const char* kZoomed[] = {kCloudTitle,  "",        kDepthTitle, kConfidenceTitle,
                                                  kCameraTitle, kFogTitle, "",          kAuraTitle};
        if (i % 15 == 0)
            viewer_->setZoomedPanel(kZoomed[i / 15 % std::size(kZoomed)]);
        frame(i / 60.0);
    }
    viewer_->setZoomedPanel("");
    show = {};
    show.fog = show.aura = show.source = show.quality = true;
    frame(5.0);
    for (const char* name : {kCloudTitle, kDepthTitle, kConfidenceTitle, kCameraTitle, kControlsTitle,
                             kFogTitle, kAuraTitle, kSourceTitle, kQualityTitle})
        EXPECT_NE(ImGui::FindWindowByName(name), nullptr) << name;
    EXPECT_GT(viewer_->summary().frames.shown, 2u);
}

TEST_F(UiTest, ClickingHighOnlyRaisesTheLevelAndRemovesPointsFromTheCloud) {
    viewer_->settings().cloud.motion.enabled = false;
    frame(0.0);
    const auto before = cloudSnapshot(0.0);
    const auto radio = locate(kControlsTitle, "High only [3]");
    ASSERT_TRUE(radio.has_value());
    click(*radio, 0.0);
    EXPECT_EQ(viewer_->settings().cloud.minConfidence, frame::Confidence::High);
    const auto after = cloudSnapshot(0.0);
    EXPECT_LT(litPixels(after), litPixels(before) * 9 / 10) << "low and medium points are no longer drawn";
    EXPECT_GT(litPixels(after), 1000u) << "high-confidence points remain";
}

TEST_F(UiTest, TheAutoRotateCheckboxStopsAndStartsTheMotion) {
    // Noise-free frames are all identical, so any change between snapshots comes from the view alone.
    devices::SyntheticConfig exact = smallScene();
    exact.noise = false;
    ASSERT_NO_FATAL_FAILURE(startViewer(exact));
    const auto box = locate(kControlsTitle, "Auto-rotate [R]");
    ASSERT_TRUE(box.has_value());
    ASSERT_TRUE(viewer_->settings().cloud.motion.enabled);
    click(*box, 0.0);
    ASSERT_FALSE(viewer_->settings().cloud.motion.enabled);
    EXPECT_EQ(cloudSnapshot(1.0), cloudSnapshot(3.0)) << "without rotation the view stands still";
    click(*box, 0.0);
    ASSERT_TRUE(viewer_->settings().cloud.motion.enabled);
    EXPECT_NE(cloudSnapshot(1.0), cloudSnapshot(3.0)) << "with rotation the view moves over time";
}

TEST_F(UiTest, TheCloudOnTheScreenIsThePanelsPictureCopiedPixelForPixel) {
    // The cloud reaches the window by a framebuffer copy in the middle of ImGui's drawing: it must land
    // upright, at the panel's content origin, at its size.
    ASSERT_NO_FATAL_FAILURE(startViewer(smallScene()));
    for (int i = 0; i < 3; ++i)
        frame(0.1 * i); // the cloud target takes the panel's size after the first frame
    const ImGuiWindow* w = ImGui::FindWindowByName(kCloudTitle);
    ASSERT_NE(w, nullptr);
    const render::RenderTarget& cloud = renderer_.cloudTarget();
    const std::vector<std::uint8_t> picture = cloud.readRgba(), screen = gui_.target().readRgba();
    ASSERT_GT(litPixels(picture), picture.size() / 4 / 20) << "a cloud to compare";
    const int x0 = static_cast<int>(w->DC.CursorStartPos.x), y0 = static_cast<int>(w->DC.CursorStartPos.y);
    ASSERT_LE(x0 + cloud.width(), gui_.target().width());
    ASSERT_LE(y0 + cloud.height(), gui_.target().height());
    std::size_t compared = 0, different = 0;
    // Below the zoom button drawn over the picture, inside the window's one-pixel border.
    for (int y = 48; y + 1 < cloud.height(); ++y)
        for (int x = 1; x + 1 < cloud.width(); ++x, ++compared) {
            const std::size_t p = (static_cast<std::size_t>(y) * cloud.width() + x) * 4;
            const std::size_t s = (static_cast<std::size_t>(y0 + y) * gui_.target().width() + x0 + x) * 4;
            different += !std::equal(&picture[p], &picture[p] + 3, &screen[s]);
        }
    EXPECT_GT(compared, 10000u);
    EXPECT_EQ(different, 0u) << "of " << compared << " pixels";
    EXPECT_TRUE(w->Flags & ImGuiWindowFlags_NoBackground) << "no background is filled under the copy";
}

TEST_F(UiTest, DraggingTheCloudOrbitsTheView) {
    viewer_->settings().cloud.motion.enabled = false;
    frame(0.0);
    const auto before = cloudSnapshot(0.0);
    ImGuiWindow* w = ImGui::FindWindowByName(kCloudTitle);
    ASSERT_NE(w, nullptr);
    ImVec2 p{w->Pos.x + w->Size.x * 0.5f, w->Pos.y + w->Size.y * 0.5f};
    gui_.io().MousePos = p;
    frame(0.0);
    gui_.io().MouseDown[0] = true;
    for (int i = 0; i < 8; ++i) {
        p.x += 10.0f;
        gui_.io().MousePos = p;
        frame(0.0);
    }
    gui_.io().MouseDown[0] = false;
    frame(0.0);
    EXPECT_GT(viewer_->settings().cloud.orbit.yawRadians, 0.4f) << "80 px of drag turns the view";
    EXPECT_EQ(w->Pos.x, ImGui::FindWindowByName(kCloudTitle)->Pos.x) << "the drag must not move the window";
    EXPECT_NE(cloudSnapshot(0.0), before);
}

TEST_F(UiTest, WheelZoomsAndDoubleClickResetsTheView) {
    ImGuiWindow* w = ImGui::FindWindowByName(kCloudTitle);
    ASSERT_NE(w, nullptr);
    gui_.io().MousePos = {w->Pos.x + w->Size.x * 0.5f, w->Pos.y + w->Size.y * 0.5f};
    frame(0.0);
    gui_.io().MouseWheel = 3.0f;
    frame(0.0);
    EXPECT_GT(viewer_->settings().cloud.orbit.zoom, 1.3f);
    gui_.io().MouseDown[0] = true;
    frame(0.0);
    gui_.io().MouseDown[0] = false;
    frame(0.0);
    gui_.io().MouseDown[0] = true;
    frame(0.0);
    gui_.io().MouseDown[0] = false;
    frame(0.0);
    EXPECT_FLOAT_EQ(viewer_->settings().cloud.orbit.zoom, 1.0f);
    EXPECT_EQ(viewer_->anchors().size(), 0u) << "a double-click leaves no anchor behind";
}

TEST_F(UiTest, ShortcutsChangeLevelRotationAndControls) {
    pressKey('2', 0.0);
    EXPECT_EQ(viewer_->settings().cloud.minConfidence, frame::Confidence::Medium);
    pressKey('R', 0.0);
    EXPECT_FALSE(viewer_->settings().cloud.motion.enabled);
    pressKey('C', 0.0);
    EXPECT_FALSE(viewer_->settings().panels.controls);
}

TEST_F(UiTest, ProcessingTogglesReachThePipelineAndTheStatusLine) {
    ASSERT_NO_FATAL_FAILURE(openControlsGroup("Processing"));
    const auto upsampling = locate(kControlsTitle, "Guided upsampling");
    ASSERT_TRUE(upsampling.has_value());
    click(*upsampling, 0.0);
    ASSERT_TRUE(viewer_->settings().processing.upsampling);
    const auto smoothing = locate(kControlsTitle, "Temporal smoothing");
    ASSERT_TRUE(smoothing.has_value());
    click(*smoothing, 0.0);
    ASSERT_TRUE(viewer_->settings().processing.smoothing);
    pressKey('F', 0.0);
    pressKey('A', 0.0);
    for (int i = 0; i < 6; ++i)
        nextFrame(i / 60.0);
    // Half the 640x480 camera image: one point per upsampled pixel.
    EXPECT_EQ(viewer_->summary().depthWidth, 320);
    EXPECT_EQ(viewer_->summary().depthHeight, 240);
    EXPECT_TRUE(shown().depth.smoothed);
    EXPECT_TRUE(shown().depth.upsampled);
    EXPECT_GT(renderer_.fogTexture().width(), 0);
    EXPECT_GT(renderer_.auraTexture().width(), 0);
    std::vector<std::string> names;
    for (const auto& t : viewer_->statusLine().stageMedians)
        names.push_back(t.name);
    for (const char* expected : {"smoothing", "upsampling", "fog", "aura"})
        EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
}

TEST_F(UiTest, StatusLineReportsSourceFramesAndTheStagesThatRun) {
    for (int i = 0; i < 30; ++i)
        nextFrame(i / 60.0);
    // The status lists what ran within the last second: let the one-off start-up work fall out of it.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (int i = 30; i < 40; ++i)
        nextFrame(i / 60.0);
    const StatusLine s = viewer_->statusLine();
    EXPECT_NE(s.source.find("synthetic"), std::string::npos);
    EXPECT_EQ(s.state, "streaming");
    EXPECT_GE(s.frames.shown, 30u);
    EXPECT_GE(s.frames.delivered, s.frames.shown + s.frames.dropped);
    EXPECT_EQ(s.pointsDrawn, shown().pointCount);
    std::vector<std::string> names;
    for (const auto& t : s.stageMedians)
        names.push_back(t.name);
    for (const char* expected : {"cloud", "upload", "point count"})
        EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
    // The scene has sensor confidence: nothing is estimated, so the stage is not listed. Its camera image
    // never changes: the points' colours were made once, and are not listed either.
    for (const char* idle : {"confidence estimate", "point colours"})
        EXPECT_EQ(std::find(names.begin(), names.end(), idle), names.end()) << idle;
    EXPECT_EQ(instrument_->processor().stageRuns("point colours"), 1u);
}

// A source without depth: the viewer keeps running and says why there is nothing to show.
class NoDepthDevice final : public devices::Device {
public:
    std::string description() const override { return "color-only camera"; }
    devices::Capabilities capabilities() const override { return {.color = true}; }

protected:
    Status doOpen() override { return {}; }
    Status doStart() override { return {}; }
    void doStop() override {}
    devices::CaptureResult doCapture(std::chrono::milliseconds) override { return {}; }
};

class UiSourceTest : public UiTest {
protected:
    void SetUp() override { ASSERT_NO_FATAL_FAILURE(initGl()); }
};

TEST_F(UiSourceTest, UnsupportedDeviceIsShownNotCrashed) {
    start(std::make_unique<NoDepthDevice>(), "color-only");
    EXPECT_FALSE(instrument_->status().running);
    EXPECT_EQ(instrument_->status().message, devices::Session::kNoDepthMessage);
    for (int i = 0; i < 10; ++i) {
        gui_.newFrame(1.0f / 60.0f);
        EXPECT_FALSE(viewer_->update(i / 60.0));
        viewer_->drawUi();
        gui_.render();
    }
    EXPECT_EQ(viewer_->statusLine().message, devices::Session::kNoDepthMessage);
    EXPECT_EQ(viewer_->cloudMessage(), devices::Session::kNoDepthMessage);
}

TEST_F(UiSourceTest, TheLastFrameStaysWithADisconnectedNote) {
    start(std::make_unique<FailingCamera>(3, devices::CaptureResult::Kind::Disconnected,
                                          "unplugged camera: No such device"),
          "unplugged");
    // Until the camera is gone and the frames it sent have been processed and shown: bounded in time, since
    // a sanitized build needs many more window frames for it.
    frameUntil([&] { return viewer_->statusLine().state == "disconnected" && viewer_->shown(); });
    EXPECT_EQ(viewer_->statusLine().state, "disconnected");
    ASSERT_NE(viewer_->shown(), nullptr) << "the view keeps the last frame";
    EXPECT_NE(viewer_->cloudMessage().find("Disconnected"), std::string::npos);
}

} // namespace
} // namespace dc::ui::test
