// Headless UI tests: the real panel functions in Debian's ImGui 1.86 (IM_ASSERT live), drawn with the
// OpenGL3 renderer into an offscreen target on Mesa llvmpipe, driven by injected mouse and keyboard input.

#include "devices/synthetic_device.h"
#include "render/gl_context.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <gtest/gtest.h>
#include <imgui_internal.h>

#include <optional>

namespace dc::ui {
namespace {

devices::SyntheticConfig smallScene() {
    devices::SyntheticConfig c;
    c.cameraWidth = 640; // the image only colors points here; a small one keeps the suite fast
    c.cameraHeight = 480;
    c.fps = 120.0;
    return c;
}

class UiTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto ctx = render::EglContext::createHeadless();
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        context_.emplace(std::move(*ctx));
        ASSERT_TRUE(gui_.init(1280, 720).ok());
        startViewer(smallScene());
    }

    void startViewer(const devices::SyntheticConfig& config) {
        viewer_ = std::make_unique<Viewer>(std::make_unique<devices::SyntheticDevice>(config), Settings{});
        ASSERT_TRUE(viewer_->init().ok());
        ASSERT_TRUE(viewer_->sourceRunning()) << viewer_->sourceMessage();
        // Let the first frame arrive so every panel has content.
        ASSERT_TRUE(viewer_->update(0.0, std::chrono::seconds(5)));
        frame(0.0);
    }

    void TearDown() override { viewer_.reset(); }

    // One UI frame at time t: the viewer renders, the panels are drawn with whatever input is set.
    void frame(double t) {
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(t);
        viewer_->drawUi();
        gui_.render();
    }

    // Finds a widget by label inside a panel by hovering candidate positions until ImGui reports the
    // widget's ID as hovered: no coordinates are hard-coded, so a layout change cannot fool the test.
    std::optional<ImVec2> locate(const char* window, const char* label) {
        ImGuiWindow* w = ImGui::FindWindowByName(window);
        if (!w)
            return std::nullopt;
        const ImGuiID id = w->GetID(label);
        for (float y = w->Pos.y; y < w->Pos.y + w->Size.y; y += 3.0f) {
            for (float x = w->Pos.x + 12.0f; x < w->Pos.x + w->Size.x * 0.6f; x += 24.0f) {
                gui_.io().MousePos = ImVec2(x, y);
                gui_.newFrame(1.0f / 60.0f);
                viewer_->drawUi();
                ImGui::EndFrame();
                if (ImGui::GetCurrentContext()->HoveredId == id)
                    return ImVec2(x, y);
            }
        }
        return std::nullopt;
    }

    void click(ImVec2 at, double t) {
        gui_.io().MousePos = at;
        frame(t);
        gui_.io().MouseDown[0] = true;
        frame(t);
        gui_.io().MouseDown[0] = false;
        frame(t);
    }

    void pressKey(int key, double t) {
        gui_.io().KeysDown[key] = true;
        frame(t);
        gui_.io().KeysDown[key] = false;
        frame(t);
    }

    std::vector<std::uint8_t> cloudSnapshot(double t) {
        viewer_->update(t);
        return viewer_->cloudTarget().readRgba();
    }

    static std::size_t litPixels(const std::vector<std::uint8_t>& rgba) {
        std::size_t n = 0;
        for (std::size_t i = 0; i < rgba.size(); i += 4)
            n += (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
        return n;
    }

    std::optional<render::EglContext> context_;
    HeadlessUi gui_;
    std::unique_ptr<Viewer> viewer_;
};

TEST_F(UiTest, EveryPanelSurvivesHundredsOfFramesBeingShownAndHidden) {
    PanelVisibility& show = viewer_->settings().panels;
    for (int i = 0; i < 300; ++i) {
        show.cloud = i % 50 < 40;
        show.depth = i % 30 < 20;
        show.confidence = i % 70 < 50;
        show.camera = i % 20 < 15;
        show.controls = i % 90 < 80;
        frame(i / 60.0);
    }
    show = {};
    frame(5.0);
    for (const char* name : {kCloudTitle, kDepthTitle, kConfidenceTitle, kCameraTitle, kControlsTitle})
        EXPECT_NE(ImGui::FindWindowByName(name), nullptr) << name;
    EXPECT_GT(viewer_->summary().framesShown, 2u);
}

TEST_F(UiTest, ClickingHighOnlyRaisesTheLevelAndRemovesPointsFromTheCloud) {
    viewer_->settings().cloud.motion.enabled = false;
    frame(0.0);
    const auto before = cloudSnapshot(0.0);
    const auto radio = locate(kControlsTitle, "High only [3]");
    ASSERT_TRUE(radio.has_value());
    click(*radio, 0.0);
    EXPECT_EQ(viewer_->settings().cloud.minConfidence, devices::Confidence::High);
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
}

TEST_F(UiTest, ShortcutsChangeLevelRotationAndControls) {
    pressKey('2', 0.0);
    EXPECT_EQ(viewer_->settings().cloud.minConfidence, devices::Confidence::Medium);
    pressKey('R', 0.0);
    EXPECT_FALSE(viewer_->settings().cloud.motion.enabled);
    pressKey('C', 0.0);
    EXPECT_FALSE(viewer_->settings().panels.controls);
}

TEST_F(UiTest, UnavailableStagesAreDisabledAndCannotBeSwitchedOn) {
    const auto box = locate(kControlsTitle, "Guided upsampling");
    ASSERT_TRUE(box.has_value()) << "the toggle is shown, disabled";
    click(*box, 0.0);
    EXPECT_FALSE(viewer_->settings().processing.upsampling);
}

TEST_F(UiTest, StatusLineReportsSourceRatesAndStages) {
    for (int i = 0; i < 30; ++i) {
        viewer_->update(i / 60.0, std::chrono::milliseconds(200));
        frame(i / 60.0);
    }
    const StatusLine s = viewer_->statusLine();
    EXPECT_NE(s.source.find("synthetic"), std::string::npos);
    EXPECT_EQ(s.state, "streaming");
    EXPECT_GT(s.deviceFps, 10.0);
    EXPECT_GT(s.viewerFps, 1.0);
    EXPECT_GT(s.pointsDrawn, 10000u);
    std::vector<std::string> names;
    for (const auto& t : s.stageMedians)
        names.push_back(t.name);
    for (const char* expected : {"cloud", "panels", "process", "upload"})
        EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
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

TEST(UiNoDepth, UnsupportedDeviceIsShownNotCrashed) {
    auto ctx = render::EglContext::createHeadless();
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    HeadlessUi gui;
    ASSERT_TRUE(gui.init(800, 600).ok());
    Viewer viewer(std::make_unique<NoDepthDevice>(), Settings{});
    ASSERT_TRUE(viewer.init().ok());
    EXPECT_FALSE(viewer.sourceRunning());
    EXPECT_EQ(viewer.sourceMessage(), devices::Session::kNoDepthMessage);
    for (int i = 0; i < 10; ++i) {
        gui.newFrame(1.0f / 60.0f);
        EXPECT_FALSE(viewer.update(i / 60.0));
        viewer.drawUi();
        gui.render();
    }
    EXPECT_EQ(viewer.statusLine().message, devices::Session::kNoDepthMessage);
}

} // namespace
} // namespace dc::ui
