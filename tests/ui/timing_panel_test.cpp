// The Timing panel in the real viewer: opened from the View menu on a camera-like synthetic source whose
// driver sequence skips frames, it shows the model's figures (read back from what ImGui drew, through its
// text log) and the frames lost in the camera that the test planted.

#include "base/clock.h"
#include "devices/frame_pacer.h"
#include "ui/panels.h"
#include "ui_fixture.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

namespace dc::ui::test {
namespace {

constexpr std::uint64_t kFrames = 40;

// The driver's sequence of the i-th frame: one lost after every fourth, as a camera on a busy USB bus.
std::uint32_t driverSequence(std::uint64_t i) {
    return static_cast<std::uint32_t>(i + i / 4);
}

// kFrames synthetic frames at 60 fps, stamped as uvcvideo stamps them (start of exposure, CLOCK_MONOTONIC,
// the driver's sequence), then silence: the figures stop changing, so the test can compare them.
class FiniteCamera final : public devices::Device {
public:
    FiniteCamera() : scene_(smallScene()) {}
    std::string description() const override { return "finite camera"; }
    devices::Capabilities capabilities() const override {
        return {.sceneDepth = true, .confidence = true, .color = true, .monotonicTimestamps = true};
    }

protected:
    Status doOpen() override { return scene_.open(); }
    Status doStart() override {
        pacer_.setRate(60.0);
        pacer_.restart();
        return {};
    }
    void doStop() override {}
    devices::CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        if (next_ == kFrames || !pacer_.waitForNext(timeout))
            return {devices::CaptureResult::Kind::Timeout, nullptr, {}};
        auto f = std::make_shared<frame::Frame>(*scene_.makeFrame(next_, static_cast<double>(next_) / 60.0));
        f->timestampNs = base::monotonicNowNs();
        f->timing.depth = {.driverSequence = driverSequence(next_),
                           .sensorNs = f->timestampNs,
                           .source = frame::TimestampSource::StartOfExposure,
                           .monotonic = true,
                           .exposureUs = std::nullopt};
        ++next_;
        return {devices::CaptureResult::Kind::Frame, std::move(f), {}};
    }

private:
    devices::SyntheticDevice scene_;
    devices::FramePacer pacer_;
    std::uint64_t next_ = 0;
};

class TimingPanelTest : public UiTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(initGl());
        ASSERT_NO_FATAL_FAILURE(start(std::make_unique<FiniteCamera>(), "finite camera"));
        frame(0.0);
    }

    // Opens the View menu (after File on the bar) and clicks its Timing entry, as a person would.
    void openFromViewMenu() {
        ImGuiWindow* bar = ImGui::FindWindowByName("##MainMenuBar");
        ASSERT_NE(bar, nullptr);
        const auto viewMenuOpen = [&] {
            ImGuiWindow* menu = ImGui::FindWindowByName("##Menu_00");
            return menu && menu->Active && locate("##Menu_00", "Reset layout", 1.0f, 8.0f).has_value();
        };
        for (float x = bar->Pos.x + 4.0f; x < bar->Pos.x + 160.0f && !viewMenuOpen(); x += 6.0f)
            click({x, bar->Pos.y + bar->Size.y * 0.5f}, 0.0);
        const auto entry = locate("##Menu_00", kTimingTitle, 1.0f, 8.0f);
        ASSERT_TRUE(entry.has_value()) << "the View menu lists the Timing panel";
        click(*entry, 0.0);
        frame(0.0);
    }

    // The panel drawn with `timing`, every text it draws logged to a file: what it shows, as text. ImGui
    // ends logging at the End() of any window, so it starts inside the panel's own window (a Begin of a
    // window already begun appends to it).
    std::string panelText(const engine::TimingSummary& timing) {
        const std::string path = ::testing::TempDir() + "timing-panel.txt";
        gui_.newFrame(1.0f / 60.0f);
        bool open = true;
        ImGui::Begin(kTimingTitle, &open);
        ImGui::LogToFile(-1, path.c_str());
        drawTimingPanel(timing, &open);
        ImGui::End();
        gui_.render();
        std::ifstream in(path);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
};

std::string figures(const char* what, const engine::DurationFigures& d) {
    char line[160];
    std::snprintf(line, sizeof line, "%s: median %.2f ms, p99 %.2f ms (%zu frames)", what, d.medianMs,
                  d.p99Ms, d.count);
    return line;
}

TEST_F(TimingPanelTest, OpenedFromTheViewMenuItShowsTheModelsFiguresAndTheFramesTheCameraLost) {
    ASSERT_FALSE(viewer_->settings().panels.timing);
    ASSERT_NO_FATAL_FAILURE(openFromViewMenu());
    ASSERT_TRUE(viewer_->settings().panels.timing);
    ASSERT_NE(ImGui::FindWindowByName(kTimingTitle), nullptr);
    // Room for every line: text outside the window is not drawn, so not logged either.
    ImGui::SetWindowSize(kTimingTitle, {640.0f, 700.0f});
    ASSERT_TRUE(frameUntil([&] {
        const engine::TimingSummary t = instrument_->timing();
        return t.delivered == kFrames && t.shown + t.drops.afterArrival() == kFrames;
    })) << "every frame shown or dropped";

    const engine::TimingSummary t = instrument_->timing();
    ASSERT_EQ(t.delivered, kFrames);
    const std::string text = panelText(t);
    // The frames the camera lost: the driver counted driverSequence(last) + 1, the application got kFrames.
    const std::uint64_t lost = driverSequence(kFrames - 1) + 1 - kFrames;
    EXPECT_EQ(t.drops.cameraUsb, lost);
    const std::string expected[] = {
        "frames: " + std::to_string(t.delivered) + " delivered, " + std::to_string(t.shown) + " shown",
        "camera/USB (driver sequence gaps): " + std::to_string(lost),
        "replaced before processing: " + std::to_string(t.drops.replacedBeforeProcessing),
        "skipped (before a seek, or delivered twice): " + std::to_string(t.drops.skipped),
        "replaced before display: " + std::to_string(t.drops.replacedBeforeDisplay),
        figures("arrival -> screen", t.arrivalToShown),
        figures("start of exposure -> screen", t.sensorToShown),
        figures("processing", t.processing),
        "depth: " + std::to_string(kFrames) + " frames, timestamps: start of exposure, CLOCK_MONOTONIC",
        "driver sequence " + std::to_string(driverSequence(kFrames - 1)),
        figures("interval", t.depth.intervals),
    };
    for (const std::string& line : expected)
        EXPECT_NE(text.find(line), std::string::npos) << "not shown: " << line << "\nshown:\n" << text;
    EXPECT_GT(t.sensorToShown.count, 0u);
    ASSERT_FALSE(t.depth.histogram.counts.empty());
    char range[64];
    std::snprintf(range, sizeof range, "%.2f .. %.2f ms", t.depth.histogram.lowMs,
                  t.depth.histogram.lowMs +
                      t.depth.histogram.binMs * static_cast<double>(t.depth.histogram.counts.size()));
    EXPECT_NE(text.find(range), std::string::npos) << "the histogram's range: " << range;
    float binned = 0.0f;
    for (const float c : t.depth.histogram.counts)
        binned += c;
    EXPECT_EQ(static_cast<std::size_t>(binned), t.depth.intervals.count) << "every interval in one bin";
}

TEST(TimingPanelSettingsTest, ItsVisibilityIsSavedAndRestored) {
    ASSERT_FALSE(Settings{}.panels.timing);
    Settings s;
    s.panels.timing = true;
    const std::string saved = settingsToJson(s);
    EXPECT_NE(saved.find("\"timing\""), std::string::npos) << saved;
    const Expected<Settings> back = settingsFromJson(saved);
    ASSERT_TRUE(back);
    EXPECT_TRUE(back->panels.timing);
}

} // namespace
} // namespace dc::ui::test
