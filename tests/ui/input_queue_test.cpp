// No lost input at a slow frame rate: every tap and click that happens between two frames (as at 3 fps, a
// 100 ms tap does) reaches ImGui 1.86 through the InputQueue exactly once, as tool/gui.cpp wires it.

#include "ui/input_queue.h"
#include "ui/panels.h"
#include "ui_fixture.h"

namespace dc::ui::test {
namespace {

// A forced slow frame: what the viewer's frames take when processing or the GPU falls behind.
constexpr float kSlowFrameSeconds = 0.3f;
constexpr int kTaps = 10;

class InputQueueTest : public UiTest {
protected:
    // One slow frame fed as the tool feeds it: the queue applies its events before ImGui's frame starts.
    // Counts how often ImGui reports a press of '3' in the frame.
    void queuedFrame() {
        queue_.apply(gui_.io());
        slowFrame();
    }
    void slowFrame() {
        gui_.newFrame(kSlowFrameSeconds);
        threePressed_ += ImGui::IsKeyPressed('3', false);
        viewer_->update(0.0);
        viewer_->drawUi();
        gui_.render();
        viewer_->presented();
    }
    // Slow frames until the queue has handed everything over (and one more, for the last release).
    void drain() {
        for (int i = 0; i < 4 * kTaps && queue_.pending() > 0; ++i)
            queuedFrame();
        queuedFrame();
    }
    void tap(int key) {
        queue_.push({InputEvent::Kind::Key, key, true});
        queue_.push({InputEvent::Kind::Key, key, false});
    }
    void clickAt(ImVec2 at) {
        queue_.push({InputEvent::Kind::CursorPos, 0, false, at.x, at.y});
        queue_.push({InputEvent::Kind::MouseButton, 0, true});
        queue_.push({InputEvent::Kind::MouseButton, 0, false});
    }

    InputQueue queue_;
    int threePressed_ = 0;
};

TEST_F(InputQueueTest, TenTapsEachInsideOneSlowFrameAreEachSeenExactlyOnce) {
    for (int i = 0; i < kTaps; ++i) {
        viewer_->settings().cloud.minConfidence = frame::Confidence::Low;
        tap('3');
        const int before = threePressed_;
        queuedFrame();
        EXPECT_EQ(threePressed_, before + 1) << "tap " << i << " is seen in the frame after it";
        EXPECT_EQ(viewer_->settings().cloud.minConfidence, frame::Confidence::High) << "tap " << i;
        drain();
    }
    EXPECT_EQ(threePressed_, kTaps) << "no tap is seen twice";
}

TEST_F(InputQueueTest, TenClicksEachInsideOneSlowFrameToggleTheCheckboxTenTimes) {
    viewer_->settings().cloud.motion.enabled = true;
    const auto box = locate(kControlsTitle, "Auto-rotate [R]");
    ASSERT_TRUE(box.has_value());
    bool last = viewer_->settings().cloud.motion.enabled;
    int toggles = 0;
    // The user clicks once per slow frame; the queue spreads each click's press and release over frames.
    const auto frameCountingToggles = [&] {
        queuedFrame();
        toggles += viewer_->settings().cloud.motion.enabled != last;
        last = viewer_->settings().cloud.motion.enabled;
    };
    for (int i = 0; i < kTaps; ++i) {
        clickAt(*box);
        frameCountingToggles();
    }
    for (int i = 0; i < 4 * kTaps && queue_.pending() > 0; ++i)
        frameCountingToggles();
    frameCountingToggles();
    EXPECT_EQ(queue_.pending(), 0u);
    EXPECT_EQ(toggles, kTaps);
    EXPECT_TRUE(viewer_->settings().cloud.motion.enabled) << "an even number of toggles";
}

// Why the queue exists: ImGui 1.86 reads keys and buttons as state once per frame, so the same taps and
// clicks written straight into ImGuiIO between two frames are lost.
TEST_F(InputQueueTest, WithoutTheQueueTheSameTapsAndClicksAreLost) {
    viewer_->settings().cloud.motion.enabled = true;
    const auto box = locate(kControlsTitle, "Auto-rotate [R]");
    ASSERT_TRUE(box.has_value());
    ImGuiIO& io = gui_.io();
    for (int i = 0; i < kTaps; ++i) {
        viewer_->settings().cloud.minConfidence = frame::Confidence::Low;
        io.KeysDown['3'] = true;
        io.KeysDown['3'] = false;
        io.MousePos = *box;
        io.MouseDown[0] = true;
        io.MouseDown[0] = false;
        slowFrame();
        EXPECT_EQ(viewer_->settings().cloud.minConfidence, frame::Confidence::Low);
        EXPECT_TRUE(viewer_->settings().cloud.motion.enabled);
    }
    EXPECT_EQ(threePressed_, 0);
}

} // namespace
} // namespace dc::ui::test
