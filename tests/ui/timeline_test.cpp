// Headless UI tests of replay: the timeline steps and seeks to exact frames, keys drive it, the record
// button records, and an export started from the UI writes the same files as `depthcloud export`.

#include "base/log.h"
#include "devices/source_spec.h"
#include "ui_fixture.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

std::map<std::string, std::string> filesUnder(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file())
            continue;
        std::ifstream in(e.path(), std::ios::binary);
        files[fs::relative(e.path(), dir).string()] = {std::istreambuf_iterator<char>(in), {}};
    }
    return files;
}

class TimelineTest : public UiTest {
protected:
    void SetUp() override {
        UiTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        dir_ = fs::temp_directory_path() / ("dc-timeline-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        recording_ = (dir_ / "scene.dcrec").string();
        // A recording made by the real recorder, the same path as `depthcloud record`.
        ASSERT_TRUE(instrument_->startRecording(recording_).ok());
        for (int i = 0; i < 200 && instrument_->recording().frames < kFrames; ++i)
            viewer_->update(0.0, std::chrono::milliseconds(20));
        ASSERT_TRUE(instrument_->stopRecording().ok());
        ASSERT_TRUE(fs::exists(recording_));
        ASSERT_TRUE(viewer_->openSource("replay:" + recording_ + ":paused").ok());
        ASSERT_NE(instrument_->replay(), nullptr);
        waitForIndex(0);
    }

    void TearDown() override {
        UiTest::TearDown();
        fs::remove_all(dir_);
    }

    // Runs the viewer until it shows frame `index` of the replay; false if it never does.
    bool waitForIndex(std::size_t index) {
        for (int i = 0; i < 100; ++i) {
            viewer_->update(0.0, std::chrono::milliseconds(20));
            frame(0.0);
            const auto& s = viewer_->shown();
            if (s && s->frame->replay && s->frame->replay->index == index)
                return true;
        }
        return false;
    }

    std::size_t shownIndex() const { return shown().frame->replay->index; }

    static constexpr std::uint64_t kFrames = 24;
    fs::path dir_;
    std::string recording_;
};

// The crash a person met: a replay open, the source picker shown, "synthetic" clicked. The frame that
// chose it went on to draw the timeline of the replay the switch had just ended.
TEST_F(TimelineTest, ChoosingAnotherSourceInThePickerWhileTheTimelineIsShownSwitchesAfterTheFrame) {
    viewer_->settings().panels.source = true;
    frame(0.0);
    ASSERT_NE(ImGui::FindWindowByName(kTimelineTitle), nullptr);
    const auto entry = locate(kSourceTitle, "Synthetic desk, 256x192 @ 60 Hz", 1.0f);
    ASSERT_TRUE(entry.has_value());
    click(*entry, 0.0);
    EXPECT_EQ(instrument_->replay(), nullptr);
    EXPECT_EQ(instrument_->spec(), "synthetic");
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown() && viewer_->shown()->depth.width() == 256; }));
    EXPECT_NE(viewer_->statusLine().source.find("ynthetic"), std::string::npos)
        << viewer_->statusLine().source;
    EXPECT_FALSE(ImGui::FindWindowByName(kTimelineTitle)->Active) << "no replay, no timeline";
}

// A replay that is paused changes nothing on screen, but the rates shown fall to zero instead of keeping
// the figures of when it played.
TEST_F(TimelineTest, APausedReplayShowsNoLiveRates) {
    viewer_->settings().cloud.motion.enabled = false; // a still view: nothing but the figures would change
    instrument_->replay()->setLoop(true);
    instrument_->replay()->play();
    const auto rate = [&] {
        const auto& figures = viewer_->shownFigures();
        return figures ? figures->frames.shownPerSecond + figures->frames.deliveredPerSecond : -1.0;
    };
    ASSERT_TRUE(frameUntil([&] { return rate() > 0.0; }));
    instrument_->replay()->pause();
    EXPECT_TRUE(frameUntil([&] { return rate() == 0.0; }, std::chrono::seconds(10))) << rate();
}

TEST_F(TimelineTest, SeeksAndStepsShowExactlyTheFrameAskedFor) {
    const std::size_t count = instrument_->replay()->status().count;
    ASSERT_GE(count, kFrames);
    for (const std::size_t target :
         {std::size_t{17}, std::size_t{3}, count - 1, std::size_t{0}, std::size_t{11}}) {
        instrument_->seekReplay(target);
        // The first frame accepted after the seek is the target: never a stale one in between.
        for (int i = 0; i < 100; ++i) {
            if (viewer_->update(0.0, std::chrono::milliseconds(20)))
                break;
        }
        EXPECT_EQ(shownIndex(), target);
    }
    pressKey(ImGui::GetKeyIndex(ImGuiKey_RightArrow), 0.0);
    ASSERT_TRUE(waitForIndex(12)) << "right arrow steps forward";
    pressKey(ImGui::GetKeyIndex(ImGuiKey_LeftArrow), 0.0);
    pressKey(ImGui::GetKeyIndex(ImGuiKey_LeftArrow), 0.0);
    ASSERT_TRUE(waitForIndex(10)) << "left arrow steps back";
    pressKey(ImGui::GetKeyIndex(ImGuiKey_End), 0.0);
    ASSERT_TRUE(waitForIndex(count - 1));
    pressKey(ImGui::GetKeyIndex(ImGuiKey_Home), 0.0);
    ASSERT_TRUE(waitForIndex(0));
    pressKey(ImGui::GetKeyIndex(ImGuiKey_Space), 0.0);
    EXPECT_TRUE(instrument_->replay()->status().playing) << "space plays";
}

TEST_F(TimelineTest, TheTimelineButtonsDriveTheReplay) {
    const auto next = locate(kTimelineTitle, ">", 1.0f, 6.0f);
    ASSERT_TRUE(next.has_value());
    click(*next, 0.0);
    ASSERT_TRUE(waitForIndex(1));
    const auto loop = locate(kTimelineTitle, "Loop", 1.0f);
    ASSERT_TRUE(loop.has_value());
    click(*loop, 0.0);
    EXPECT_TRUE(instrument_->replay()->status().loop);
}

TEST_F(TimelineTest, TheTimelineIsAStripUnderThePanelsAndStaysReachable) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGuiWindow* strip = ImGui::FindWindowByName(kTimelineTitle);
    ImGuiWindow* cloud = ImGui::FindWindowByName(kCloudTitle);
    ASSERT_NE(strip, nullptr);
    ASSERT_NE(cloud, nullptr);
    EXPECT_EQ(strip->Size.x, vp->Size.x) << "full width";
    EXPECT_GE(strip->Pos.y, cloud->Pos.y + cloud->Size.y) << "under the cloud, not over it";
    for (const char* side : {kDepthTitle, kCameraTitle, kControlsTitle}) {
        ImGuiWindow* w = ImGui::FindWindowByName(side);
        ASSERT_NE(w, nullptr);
        EXPECT_LE(w->Pos.y + w->Size.y, strip->Pos.y + 0.5f) << side;
    }
    // Orbit drags on the cloud bring the cloud to the front; the strip stays in front of it.
    const ImVec2 c{cloud->Pos.x + cloud->Size.x * 0.5f, cloud->Pos.y + cloud->Size.y * 0.5f};
    for (int i = 0; i < 2; ++i) {
        gui_.io().MousePos = c;
        frame(0.0);
        gui_.io().MouseDown[0] = true;
        frame(0.0);
        for (int step = 1; step <= 4; ++step) {
            gui_.io().MousePos = {c.x + 30.0f * step, c.y + 10.0f * step};
            frame(0.0);
        }
        gui_.io().MouseDown[0] = false;
        frame(0.0);
    }
    EXPECT_NE(viewer_->settings().cloud.orbit.yawRadians, 0.0f) << "the drags orbited";
    // A panel moved onto the strip and focused stays behind it: the mouse over the overlap is the strip's.
    ImGui::SetWindowPos(kCloudTitle, {cloud->Pos.x, strip->Pos.y + 10.0f});
    ImGui::SetWindowFocus(kCloudTitle);
    frame(0.0);
    const ImVec2 overlap{c.x, strip->Pos.y + strip->Size.y * 0.5f};
    ASSERT_GT(overlap.y, cloud->Pos.y) << "the cloud covers this point";
    ASSERT_LT(overlap.y, cloud->Pos.y + cloud->Size.y);
    gui_.io().MousePos = overlap;
    frame(0.0);
    EXPECT_EQ(ImGui::GetCurrentContext()->HoveredWindow, strip);
    EXPECT_TRUE(locate(kTimelineTitle, ">", 1.0f, 6.0f).has_value()) << "the strip's buttons take the mouse";
    // T (and the Panels toggle it lists) hides and shows it.
    pressKey('T', 0.0);
    EXPECT_FALSE(viewer_->settings().panels.timeline);
    EXPECT_FALSE(strip->Active);
    const auto toggle = locate(kControlsTitle, "Timeline [T]");
    ASSERT_TRUE(toggle.has_value());
    click(*toggle, 0.0);
    frame(0.0);
    EXPECT_TRUE(viewer_->settings().panels.timeline);
    EXPECT_TRUE(strip->Active);
    EXPECT_TRUE(locate(kTimelineTitle, "Loop", 1.0f).has_value());
}

TEST_F(TimelineTest, TheAutomaticRangeFollowsTheReplaySmoothly) {
    ASSERT_TRUE(viewer_->settings().depthRange.automatic) << "the default";
    const auto followed = [&] { return viewer_->depthLegend().maxMeters; };
    const auto target = [&] { return shown().automaticRange->maxMeters; };
    ASSERT_TRUE(shown().automaticRange.has_value());
    // Each step moves the range a fifth of the way to the new frame's percentiles, never past them.
    for (std::size_t index = 1; index < 12; ++index) {
        const float before = followed();
        instrument_->stepReplay(1);
        ASSERT_TRUE(waitForIndex(index));
        const float expected = before + Viewer::kRangeFollowFraction * (target() - before);
        EXPECT_NEAR(followed(), expected, 1e-4f) << "frame " << index;
    }
    EXPECT_NEAR(followed(), target(), 0.05f) << "it settles on the replay's range";
}

// Export range clicked twice with the same folder: the second export goes beside the first, numbered,
// instead of over it, and each says where it went.
TEST_F(TimelineTest, ExportingTwiceFromTheTimelineNeverWritesOverTheFirst) {
    const fs::path before = fs::current_path();
    fs::current_path(dir_); // the default folder, depthcloud-export, is relative to where the tool runs
    const fs::path here = fs::current_path();
    const auto exportOnce = [&] {
        const auto button = locate(kTimelineTitle, "Export range", 1.0f, 8.0f);
        ASSERT_TRUE(button.has_value());
        click(*button, 0.0);
        ASSERT_NE(instrument_->exportJob(), nullptr);
        // Every frame's files are written under ASan on a loaded machine too.
        ASSERT_TRUE(
            frameUntil([&] { return instrument_->exportJob()->finished(); }, std::chrono::seconds(90)));
    };
    exportOnce();
    exportOnce();
    fs::current_path(before);
    for (const char* name : {"depthcloud-export", "depthcloud-export-2"})
        EXPECT_EQ(filesUnder(dir_ / name).size(), instrument_->replay()->status().count) << name;
    // Each names its folder from the root: the tool's working directory when it started, however it changes.
    std::size_t said = 0;
    for (const LogEntry& e : viewer_->log().snapshot())
        said += e.level == LogLevel::Notice &&
                e.message.find((here / "depthcloud-export").string()) != std::string::npos;
    EXPECT_EQ(said, 2u);
}

// The export-format list opens in front of the timeline strip it belongs to, so every format can be chosen.
TEST_F(TimelineTest, TheFormatListOpensInFrontOfTheTimeline) {
    const auto combo = locate(kTimelineTitle, "##format", 1.0f, 8.0f);
    ASSERT_TRUE(combo.has_value());
    click(*combo, 0.0);
    frame(0.0);
    const ImVector<ImGuiWindow*>& order = ImGui::GetCurrentContext()->Windows;
    int strip = -1, list = -1;
    for (int i = 0; i < order.Size; ++i) {
        if (order[i] == ImGui::FindWindowByName(kTimelineTitle))
            strip = i;
        if ((order[i]->Flags & ImGuiWindowFlags_Popup) && order[i]->Active)
            list = i;
    }
    ASSERT_GE(list, 0) << "the list is open";
    EXPECT_GT(list, strip) << "drawn after (in front of) the strip";
}

TEST_F(TimelineTest, ExportFromTheUiWritesWhatTheCliWrites) {
    const fs::path ui = dir_ / "ui", cli = dir_ / "cli";
    const auto timedFrame = [&](std::vector<double>& log) {
        const auto start = std::chrono::steady_clock::now();
        viewer_->update(0.0, std::chrono::milliseconds(10));
        frame(0.0);
        log.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    };
    const auto describe = [](std::vector<double> log) {
        std::sort(log.begin(), log.end());
        char text[80];
        std::snprintf(text, sizeof text, "%zu frames, median %.1f ms, max %.1f ms", log.size(),
                      log[log.size() / 2], log.back());
        return std::string(text);
    };
    std::vector<double> before, during;
    for (int i = 0; i < 10; ++i)
        timedFrame(before);
    ASSERT_TRUE(
        instrument_->startExport(exporting::ExportFormat::Ply, ui.string(), 4, 9, viewer_->demand()).ok());
    // The UI keeps drawing while the export runs on its worker: count and time the frames drawn meanwhile.
    while (during.size() < 600 && !instrument_->exportJob()->finished())
        timedFrame(during);
    ASSERT_TRUE(instrument_->exportJob()->finished());
    ASSERT_FALSE(during.empty()) << "the export blocked the UI: it was finished before a frame was drawn";
    std::printf("UI frame time before the export: %s; during it: %s\n", describe(before).c_str(),
                describe(during).c_str());
    const auto result = instrument_->exportJob()->result();
    ASSERT_TRUE(result && result->ok()) << (result ? result->error().message : "no result");
    EXPECT_EQ((*result)->framesWritten, 5u);
    const std::string command = std::string(DEPTHCLOUD_BINARY) + " export --source replay:" + recording_ +
                                " --out " + cli.string() + " --frames 4:9 --format ply > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const auto uiFiles = filesUnder(ui);
    EXPECT_EQ(uiFiles.size(), 5u);
    EXPECT_EQ(uiFiles, filesUnder(cli));
}

} // namespace
} // namespace dc::ui::test
