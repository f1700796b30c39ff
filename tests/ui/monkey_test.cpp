// The UI monkey: seeded random sequences of what a person does, played through the real Viewer (the
// headless UI, the real engine and sources): switching among every kind of source (a vanished file and bad
// specs among them), clicking, dragging, hovering and scrolling anywhere, every shortcut, resizing the
// window from tiny to full HD, recording, snapshots. After every action it checks what must always hold.
//
// DC_MONKEY_SEED=N plays seed N's sequence of actions (the timing of the sources still varies); the seed
// of every run is printed first, so a crash names it too. DC_MONKEY_SECONDS bounds the fresh-seed run.

#include "devices/synthetic/synthetic_device.h"
#include "tests/test_data.h"
#include "ui_fixture.h"

#include <epoxy/gl.h>

#include <array>
#include <cfloat>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <execinfo.h>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

// The last actions played, for a crash's report: a signal handler can only read what is already written.
std::array<std::array<char, 256>, 16> gLastActions{};
std::size_t gActionsPlayed = 0;

void noteAction(const std::string& text) {
    std::array<char, 256>& slot = gLastActions[gActionsPlayed++ % gLastActions.size()];
    std::snprintf(slot.data(), slot.size(), "%s", text.c_str());
}

void writeError(const char* text) {
    (void)!::write(STDERR_FILENO, text, std::strlen(text));
}

// A crash names the actions that led to it and where it happened (offsets into the test binary, for
// addr2line), then ends the process as the signal would have.
void reportCrash(int signal) {
    writeError("monkey: crashed; the last actions, oldest first:\n");
    const std::size_t n = std::min(gActionsPlayed, gLastActions.size());
    for (std::size_t i = gActionsPlayed - n; i < gActionsPlayed; ++i) {
        writeError("  ");
        writeError(gLastActions[i % gLastActions.size()].data());
        writeError("\n");
    }
    void* frames[64];
    ::backtrace_symbols_fd(frames, ::backtrace(frames, 64), STDERR_FILENO);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

constexpr int kGlfwKeyEscape = 256, kGlfwKeyRight = 262, kGlfwKeyLeft = 263, kGlfwKeyHome = 268,
              kGlfwKeyEnd = 269, kGlfwKeySpace = 32;

class MonkeyTest : public UiTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(initGl());
        work_ = fs::temp_directory_path() / ("dc-monkey-" + std::to_string(::getpid()));
        fs::remove_all(work_);
        fs::create_directories(work_ / "inputs");
        previousDirectory_ = fs::current_path();
        // Everything the tool saves by default (snapshots, takes, exports) goes under the working directory.
        fs::current_path(work_);
        ASSERT_NO_FATAL_FAILURE(startViewer(smallScene()));
        const std::string take = (work_ / "inputs" / "take.dcrec").string();
        ASSERT_TRUE(instrument_->startRecording(take).ok());
        for (int i = 0; i < 200 && instrument_->recording().frames < 12; ++i)
            viewer_->update(0.0, std::chrono::milliseconds(20));
        ASSERT_TRUE(instrument_->stopRecording().ok());
        fs::copy_file(take, work_ / "inputs" / "vanishing.dcrec");
        std::ofstream(work_ / "inputs" / "notes.txt") << "not a capture\n";
        const fs::path tum = makeTumSequence(work_ / "inputs" / "tum");
        sources_ = {"synthetic",
                    "synthetic:64x48@30",
                    "synthetic:motion",
                    "synthetic:rig=rgbd",
                    "replay:" + take,
                    "replay:" + take + ":loop:speed=4",
                    "replay:" + take + ":paused",
                    "replay:" + (work_ / "inputs" / "vanishing.dcrec").string(),
                    "replay:" + tum.string(),
                    "replay:" + dc::test::dataPath("tum_frame"),
                    "replay:" + (work_ / "inputs" / "missing.dcrec").string(),
                    "synthetic:12x",
                    "nonsense:0"};
        paths_ = {take, (work_ / "inputs" / "notes.txt").string(), tum.string(),
                  dc::test::dataPath("tum_frame"), (work_ / "inputs").string()};
    }

    void TearDown() override {
        if (instrument_ && instrument_->recording().recording)
            (void)instrument_->stopRecording();
        UiTest::TearDown();
        fs::current_path(previousDirectory_);
        fs::remove_all(work_);
    }

    // A TUM RGB-D sequence of three frames, each the shared data's one real frame pair.
    static fs::path makeTumSequence(const fs::path& dir) {
        fs::create_directories(dir);
        const std::string data = dc::test::dataPath("tum_frame");
        std::ofstream rgb(dir / "rgb.txt"), depth(dir / "depth.txt");
        for (int i = 0; i < 3; ++i) {
            rgb << 1.0 + i / 30.0 << ' ' << data << "/TUM_color.png\n";
            depth << 1.0 + i / 30.0 << ' ' << data << "/TUM_depth.png\n";
        }
        return dir;
    }

    // Plays `seed`'s actions until `actions` are done or `limit` passes; returns how many were played.
    std::uint64_t play(std::uint64_t seed, std::uint64_t actions, std::chrono::seconds limit) {
        std::printf("monkey: seed %llu\n", static_cast<unsigned long long>(seed));
        std::fflush(stdout);
        SCOPED_TRACE("monkey seed " + std::to_string(seed) + " (DC_MONKEY_SEED=" + std::to_string(seed) +
                     " plays it again)");
        std::mt19937_64 random(seed);
        for (const int signal : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE})
            std::signal(signal, reportCrash);
        const auto deadline = std::chrono::steady_clock::now() + limit;
        std::uint64_t played = 0;
        for (; played < actions && std::chrono::steady_clock::now() < deadline; ++played) {
            noteAction("seed " + std::to_string(seed) + ", action " + std::to_string(played) + " starts");
            const std::string action = act(random);
            noteAction("seed " + std::to_string(seed) + ", action " + std::to_string(played) + ": " + action);
            SCOPED_TRACE("action " + std::to_string(played) + ": " + action);
            frame(0.0);
            checkInvariants();
            if (HasFailure())
                break;
        }
        return played;
    }

    std::string act(std::mt19937_64& random) {
        const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(random() % n); };
        const ImVec2 size = gui_.io().DisplaySize;
        const auto anywhere = [&] {
            return ImVec2(static_cast<float>(pick(static_cast<std::size_t>(size.x))),
                          static_cast<float>(pick(static_cast<std::size_t>(size.y))));
        };
        switch (pick(26)) {
        case 0: {
            const std::string& spec = sources_[pick(sources_.size())];
            if (spec.find("vanishing") != std::string::npos && pick(2) == 0)
                fs::remove(spec.substr(7)); // the file goes away, now or while it replays
            (void)viewer_->openSource(spec);
            return "open " + spec;
        }
        case 1: {
            const std::string& path = paths_[pick(paths_.size())];
            (void)viewer_->openPath(path);
            return "drop " + path;
        }
        case 2: {
            static constexpr int kSizes[][2] = {
                {320, 240}, {1024, 600}, {1280, 720}, {1920, 1080}, {640, 900}};
            const auto& s = kSizes[pick(std::size(kSizes))];
            EXPECT_TRUE(gui_.resize(s[0], s[1]).ok());
            return "resize " + std::to_string(s[0]) + "x" + std::to_string(s[1]);
        }
        case 3: {
            static constexpr int kKeys[] = {
                'C',           'T',          'S',           'L',          'O',
                'F',           'A',          'P',           'Z',          'R',
                'V',           '1',          '2',           '3',          kGlfwKeyEscape,
                kGlfwKeySpace, kGlfwKeyLeft, kGlfwKeyRight, kGlfwKeyHome, kGlfwKeyEnd};
            const int key = kKeys[pick(std::size(kKeys))];
            pressKey(key, 0.0);
            return "key " + std::to_string(key);
        }
        case 4:
            if (instrument_->recording().recording)
                (void)instrument_->stopRecording();
            else
                (void)instrument_->startTake(".", {});
            return "record button";
        case 5: {
            const ImVec2 from = anywhere(), to = anywhere();
            drag(from, to);
            return "drag";
        }
        case 6: {
            gui_.io().MousePos = anywhere();
            gui_.io().MouseWheel = pick(2) ? 1.0f : -1.0f;
            frame(0.0);
            gui_.io().MouseWheel = 0.0f;
            return "wheel";
        }
        case 7:
        case 8:
            gui_.io().MousePos = anywhere();
            return "hover";
        case 9:
            gui_.io().MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
            return "mouse leaves";
        case 10:
            std::this_thread::sleep_for(std::chrono::milliseconds(pick(60)));
            return "wait";
        case 11:
        case 12:
            clickInSourcePanel(random);
            return "pick in the Source panel";
        case 22: {
            // A second or third source beside the main one, fused in its cloud (any kind, as in the picker).
            if (viewer_->companions().size() >= 2)
                return "add a source (two are open already)";
            viewer_->settings().panels.sources = true;
            const std::string& spec = sources_[pick(sources_.size())];
            (void)viewer_->addSource(spec);
            return "add source " + spec;
        }
        case 23:
            if (viewer_->companions().empty())
                return "remove a source (none)";
            viewer_->companions().remove(pick(viewer_->companions().size()));
            return "remove a source";
        case 24: {
            // A further source's own processing, or the image panels showing another source.
            const std::size_t n = viewer_->companions().size();
            if (n == 0)
                return "a further source's settings (none)";
            if (pick(2) == 0) {
                viewer_->panelSource() = pick(n + 1);
                return "image panels show source " + std::to_string(viewer_->panelSource() + 1);
            }
            SourceSettings& own = viewer_->companions()[pick(n)].own;
            own.followsMain = pick(2) == 0;
            own.processing.upsampling = pick(2) == 0;
            own.processing.smoothing = pick(2) == 0;
            own.minConfidence = static_cast<frame::Confidence>(pick(3));
            return std::string("a further source's own processing ") + (own.followsMain ? "off" : "on");
        }
        case 25:
            viewer_->settings().accumulate.enabled = !viewer_->settings().accumulate.enabled;
            return std::string("accumulate ") + (viewer_->settings().accumulate.enabled ? "on" : "off");
        default:
            clickInsideAWindow(random);
            return "click";
        }
    }

    // A click where a person clicks: inside one of the windows shown (panels, menus, popups), else anywhere.
    void clickInsideAWindow(std::mt19937_64& random) {
        std::vector<ImGuiWindow*> shown;
        for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
            if (w->Active && !(w->Flags & ImGuiWindowFlags_ChildWindow))
                shown.push_back(w);
        ImVec2 at(static_cast<float>(random() % 1000), static_cast<float>(random() % 700));
        if (!shown.empty()) {
            const ImGuiWindow* w = shown[random() % shown.size()];
            at = ImVec2(w->Pos.x + static_cast<float>(random() % std::max(1, static_cast<int>(w->Size.x))),
                        w->Pos.y + static_cast<float>(random() % std::max(1, static_cast<int>(w->Size.y))));
        }
        click(at, 0.0);
    }

    // Where a person picks a source: the Source panel (opened with its shortcut first when it is hidden).
    void clickInSourcePanel(std::mt19937_64& random) {
        const ImGuiWindow* panel = ImGui::FindWindowByName(kSourceTitle);
        if (!panel || !panel->Active) {
            pressKey('O', 0.0);
            return;
        }
        click(ImVec2(
                  panel->Pos.x + static_cast<float>(random() % std::max(1, static_cast<int>(panel->Size.x))),
                  panel->Pos.y + static_cast<float>(random() % std::max(1, static_cast<int>(panel->Size.y)))),
              0.0);
    }

    void drag(ImVec2 from, ImVec2 to) {
        gui_.io().MousePos = from;
        frame(0.0);
        gui_.io().MouseDown[0] = true;
        frame(0.0);
        gui_.io().MousePos = ImVec2((from.x + to.x) / 2, (from.y + to.y) / 2);
        frame(0.0);
        gui_.io().MousePos = to;
        frame(0.0);
        gui_.io().MouseDown[0] = false;
    }

    void checkInvariants() {
        EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
        const engine::InstrumentStatus s = instrument_->status();
        EXPECT_LE(s.frames.shown + s.frames.dropped, s.frames.delivered)
            << "shown + dropped + in flight = delivered, for " << s.source;
        for (std::size_t i = 0; i < viewer_->companions().size(); ++i) {
            const engine::InstrumentStatus c = viewer_->companions()[i].instrument().status();
            EXPECT_LE(c.frames.shown + c.frames.dropped, c.frames.delivered)
                << "each source counts its own frames, for " << c.source;
        }
        const StatusLine line = viewer_->statusLine();
        EXPECT_EQ(line.source, s.source) << "the status line names the current source";
        if (gui_.io().MousePos.x < 0.0f) {
            EXPECT_FALSE(viewer_->hoverProbe().has_value()) << "no readout once the mouse has left";
        }
    }

    // Everything written while the monkey played lies in the folders the tool saves into by default.
    void expectNothingWrittenElsewhere() {
        for (const auto& e : fs::recursive_directory_iterator(work_)) {
            const std::string top = fs::relative(e.path(), work_).begin()->string();
            const bool allowed = top == "inputs" || top == "depthcloud-snapshots" ||
                                 top.starts_with("depthcloud-recording-") ||
                                 top.starts_with("depthcloud-export");
            EXPECT_TRUE(allowed) << e.path();
        }
    }

    fs::path work_;
    fs::path previousDirectory_;
    std::vector<std::string> sources_;
    std::vector<std::string> paths_;
};

std::chrono::seconds freshRunSeconds() {
    const char* text = std::getenv("DC_MONKEY_SECONDS");
    return std::chrono::seconds(text ? std::max(1, std::atoi(text)) : 20);
}

// Seeds that met a crash before its fix, each played again: 3 chose the synthetic camera in the Source
// panel while a replay's timeline was shown, and the frame went on to draw the timeline of the replay the
// switch had ended (ReplayControl::status on a null replay, from Viewer::drawTimeline).
TEST_F(MonkeyTest, TheSeedsThatFoundCrashesStillPass) {
    for (const std::uint64_t seed : {3ull}) {
        play(seed, 400, std::chrono::seconds(60));
        ASSERT_FALSE(HasFailure());
    }
    expectNothingWrittenElsewhere();
}

// A fresh seed each run (DC_MONKEY_SEED=N to play one again), for DC_MONKEY_SECONDS.
TEST_F(MonkeyTest, AFreshSeedSurvivesEverythingAPersonDoes) {
    const char* given = std::getenv("DC_MONKEY_SEED");
    const std::uint64_t seed = given ? std::strtoull(given, nullptr, 10) : std::random_device()();
    const std::uint64_t played = play(seed, ~0ull, freshRunSeconds());
    std::printf("monkey: %llu actions\n", static_cast<unsigned long long>(played));
    EXPECT_GT(played, 10u);
    expectNothingWrittenElsewhere();
}

} // namespace
} // namespace dc::ui::test
