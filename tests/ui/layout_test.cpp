// Headless UI tests of what a new user meets first: the Controls groups fit a 1280x720 window, the menu
// lists every panel and resets the layout, the automatic depth range is the default and the fixed one a
// click away, the log panel holds the start-up messages, and a folder dropped on the window opens.

#include "tests/test_data.h"
#include "ui_fixture.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace dc::ui::test {
namespace {

ImGuiWindow* window(const char* title) {
    return ImGui::FindWindowByName(title);
}

TEST_F(UiTest, ThePanelTogglesAndTheLayoutResetFitTheControlsAt1280x720) {
    ImGuiWindow* controls = window(kControlsTitle);
    ASSERT_NE(controls, nullptr);
    // locate() only finds a widget the mouse can reach inside the window: one below its bottom edge, to be
    // scrolled to, is not found.
    for (const char* label : {"Timeline [T]", "Log [L]", "Aura [A]", "Reset layout", "Automatic range"})
        EXPECT_TRUE(locate(kControlsTitle, label).has_value())
            << label << " is not reachable without scrolling";
    EXPECT_EQ(controls->Scroll.y, 0.0f);
}

TEST_F(UiTest, ResetLayoutBringsBackTheDefaultPanelsInTheirPlaces) {
    ImGuiWindow* controls = window(kControlsTitle);
    ASSERT_NE(controls, nullptr);
    const ImVec2 home = controls->Pos;
    ImGui::SetWindowPos(kControlsTitle, {home.x + 20.0f, home.y + 40.0f});
    viewer_->settings().panels.source = true; // floats: showing it lays out nothing again
    frame(0.0);
    ASSERT_NE(controls->Pos.x, home.x);
    const auto reset = locate(kControlsTitle, "Reset layout");
    ASSERT_TRUE(reset.has_value());
    click(*reset, 0.0);
    frame(0.0);
    EXPECT_EQ(controls->Pos.x, home.x);
    EXPECT_EQ(controls->Pos.y, home.y);
    EXPECT_FALSE(viewer_->settings().panels.source);
    ASSERT_NE(window(kDepthTitle), nullptr);
    EXPECT_TRUE(window(kDepthTitle)->Active);
}

// The panels a person opens take a place beside the cloud, not over it: the stats and the log in a strip
// under it, the effect panels in the right column; no two overlap, all inside the window; hiding them
// gives the cloud its room back.
TEST_F(UiTest, OpenedPanelsAreDockedBesideTheCloudNotOverIt) {
    const float fullCloudHeight = window(kCloudTitle)->Size.y;
    PanelVisibility& show = viewer_->settings().panels;
    show.stats = show.log = show.fog = show.aura = true;
    frame(0.0);
    frame(0.0);
    const char* docked[] = {kControlsTitle, kCloudTitle, kDepthTitle, kConfidenceTitle, kCameraTitle,
                            kFogTitle,      kAuraTitle,  kStatsTitle, kLogTitle};
    const ImVec2 display = gui_.io().DisplaySize;
    for (const char* a : docked) {
        const ImGuiWindow* p = window(a);
        ASSERT_TRUE(p && p->Active) << a;
        EXPECT_GE(p->Pos.x, 0.0f) << a;
        EXPECT_LE(p->Pos.x + p->Size.x, display.x + 0.5f) << a;
        EXPECT_LE(p->Pos.y + p->Size.y, display.y + 0.5f) << a;
        for (const char* b : docked) {
            const ImGuiWindow* q = window(b);
            if (p == q)
                continue;
            const float overlapX =
                std::min(p->Pos.x + p->Size.x, q->Pos.x + q->Size.x) - std::max(p->Pos.x, q->Pos.x);
            const float overlapY =
                std::min(p->Pos.y + p->Size.y, q->Pos.y + q->Size.y) - std::max(p->Pos.y, q->Pos.y);
            EXPECT_FALSE(overlapX > 1.0f && overlapY > 1.0f) << a << " overlaps " << b;
        }
    }
    EXPECT_LT(window(kCloudTitle)->Size.y, fullCloudHeight - 100.0f) << "the strip is under the cloud";
    show.stats = show.log = show.fog = show.aura = false;
    frame(0.0);
    frame(0.0);
    EXPECT_EQ(window(kCloudTitle)->Size.y, fullCloudHeight);
}

// The window resized from 1280x720 down to 1024x600 and up to 1920x1080: the docked panels are laid out
// again for each size, wholly inside it, and a floating panel the shrink left outside comes back in reach.
TEST_F(UiTest, ThePanelsFollowTheWindowFromSmallToLarge) {
    pressKey('O', 0.0); // the Source panel floats
    frame(0.0);
    ImGui::SetWindowPos(kSourceTitle, {1150.0f, 650.0f});
    frame(0.0);
    std::map<int, float> cloudWidth;
    for (const auto& [w, h] : {std::pair{1024, 600}, std::pair{1920, 1080}, std::pair{1280, 720}}) {
        ASSERT_TRUE(gui_.resize(w, h).ok());
        frame(0.0);
        frame(0.0);
        for (const char* title : {kControlsTitle, kCloudTitle, kDepthTitle, kConfidenceTitle, kCameraTitle}) {
            const ImGuiWindow* panel = window(title);
            ASSERT_NE(panel, nullptr);
            EXPECT_GE(panel->Pos.x, 0.0f) << title << " at " << w << "x" << h;
            EXPECT_GE(panel->Pos.y, 0.0f) << title << " at " << w << "x" << h;
            EXPECT_LE(panel->Pos.x + panel->Size.x, w + 0.5f) << title << " at " << w << "x" << h;
            EXPECT_LE(panel->Pos.y + panel->Size.y, h + 0.5f) << title << " at " << w << "x" << h;
        }
        const ImGuiWindow* source = window(kSourceTitle);
        EXPECT_LT(source->Pos.x, w - 20.0f) << "the Source title bar can be grabbed at " << w << "x" << h;
        EXPECT_LT(source->Pos.y, h - 20.0f) << "the Source title bar can be grabbed at " << w << "x" << h;
        cloudWidth[w] = window(kCloudTitle)->Size.x;
    }
    EXPECT_GT(cloudWidth[1920], cloudWidth[1280] + 200.0f) << "a larger window gives the cloud the room";
    EXPECT_LT(cloudWidth[1024], cloudWidth[1280]);
}

// File is the first menu: Esc closes it as it closes any open menu, and its Quit asks the window to close.
TEST_F(UiTest, TheFileMenuClosesWithEscapeAndQuits) {
    ImGuiWindow* bar = window("##MainMenuBar");
    ASSERT_NE(bar, nullptr);
    const ImVec2 file{bar->Pos.x + 12.0f, bar->Pos.y + bar->Size.y * 0.5f};
    click(file, 0.0);
    ImGuiWindow* menu = window("##Menu_00");
    ASSERT_TRUE(menu && menu->Active);
    ASSERT_TRUE(locate("##Menu_00", "Quit", 1.0f, 8.0f).has_value()) << "the File menu is open";
    pressKey(256 /* GLFW_KEY_ESCAPE */, 0.0);
    frame(0.0);
    EXPECT_FALSE(menu->Active) << "Esc closed it";
    click(file, 0.0);
    const auto quit = locate("##Menu_00", "Quit", 1.0f, 8.0f);
    ASSERT_TRUE(quit.has_value());
    EXPECT_FALSE(viewer_->quitRequested());
    click(*quit, 0.0);
    EXPECT_TRUE(viewer_->quitRequested());
}

TEST_F(UiTest, TheViewMenuListsThePanelsAndResetsTheLayout) {
    ImGui::SetWindowPos(kControlsTitle, {500.0f, 300.0f});
    // The menu bar's items live under its own ID scope: open "View" (after "File") by clicking along the bar
    // until the menu that opens is the one with "Reset layout".
    ImGuiWindow* bar = window("##MainMenuBar");
    ASSERT_NE(bar, nullptr);
    ImGuiWindow* menu = nullptr;
    const auto viewMenuOpen = [&] {
        menu = window("##Menu_00");
        return menu && menu->Active && locate("##Menu_00", "Reset layout", 1.0f, 8.0f).has_value();
    };
    for (float x = bar->Pos.x + 4.0f; x < bar->Pos.x + 160.0f && !viewMenuOpen(); x += 6.0f)
        click({x, bar->Pos.y + bar->Size.y * 0.5f}, 0.0);
    ASSERT_NE(menu, nullptr);
    ASSERT_TRUE(menu->Active);
    // Every panel is listed, the timeline among them.
    for (const char* title : {kCloudTitle, kTimelineTitle, kLogTitle, kAuraTitle})
        EXPECT_TRUE(locate("##Menu_00", title, 1.0f, 8.0f).has_value()) << title;
    const auto reset = locate("##Menu_00", "Reset layout", 1.0f, 8.0f);
    ASSERT_TRUE(reset.has_value());
    click(*reset, 0.0);
    frame(0.0);
    EXPECT_EQ(window(kControlsTitle)->Pos.x, 0.0f);
}

TEST_F(UiTest, TheAutomaticRangeIsTheDefaultAndTheFixedRangeOneClickAway) {
    ASSERT_TRUE(Settings{}.depthRange.automatic);
    ASSERT_TRUE(viewer_->demand().automaticRange) << "the engine computes the percentiles";
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(nextFrame(0.0));
    const DepthLegend automatic = viewer_->depthLegend();
    ASSERT_TRUE(automatic.automatic);
    ASSERT_TRUE(shown().automaticRange.has_value());
    EXPECT_GT(automatic.minMeters, 0.2f) << "the desk's nearest part, not the fixed 0 m";
    EXPECT_NEAR(automatic.maxMeters, shown().automaticRange->maxMeters, 0.5f);
    const auto box = locate(kControlsTitle, "Automatic range");
    ASSERT_TRUE(box.has_value());
    click(*box, 0.0);
    EXPECT_FALSE(viewer_->settings().depthRange.automatic);
    frame(0.0);
    EXPECT_EQ(viewer_->depthLegend().minMeters, 0.0f) << "the fixed range";
    EXPECT_EQ(viewer_->depthLegend().maxMeters, 2.5f);
}

TEST_F(UiTest, TheLogPanelHoldsWhatWasLoggedBeforeItExisted) {
    viewer_.reset(); // no log sink now, as before the tool's first viewer
    logInfo("settings: start-up marker 7781");
    viewer_ = std::make_unique<Viewer>(*instrument_, renderer_, Settings{});
    bool found = false;
    for (const LogEntry& e : viewer_->log().snapshot())
        found |= e.message == "settings: start-up marker 7781";
    EXPECT_TRUE(found);
}

TEST_F(UiTest, ADroppedFolderOpensAsASourceAndAPlainOneIsRefused) {
    EXPECT_FALSE(viewer_->openPath(::testing::TempDir()).ok()) << "a folder that is no capture";
    EXPECT_EQ(instrument_->spec(), "synthetic") << "the current source keeps running";
    ASSERT_TRUE(viewer_->openPath(dc::test::dataPath("arkit_dance_stray")).ok());
    EXPECT_EQ(instrument_->spec(), "replay:" + dc::test::dataPath("arkit_dance_stray"));
    ASSERT_NE(instrument_->replay(), nullptr);
    ASSERT_TRUE(nextFrame(0.0));
    EXPECT_TRUE(shown().frame->replay.has_value()) << "a frame of the capture";
}

} // namespace
} // namespace dc::ui::test
