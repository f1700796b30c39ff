#pragma once

#include <imgui.h>

#include <array>
#include <cstddef>
#include <deque>

namespace dc::ui {

// One input event as the window system reported it.
struct InputEvent {
    enum class Kind { Key, Char, MouseButton, CursorPos, Scroll };
    Kind kind = Kind::Key;
    int code = 0;      // Key: the key code (GLFW's, which ImGui 1.86's KeysDown is indexed by); MouseButton:
                       // the button (0 left, 1 right, 2 middle); Char: the Unicode code point
    bool down = false; // Key, MouseButton: pressed or released
    float x = 0.0f;    // CursorPos: window coordinates; Scroll: the offsets
    float y = 0.0f;
};

// Debian's ImGui 1.86 reads input as state once per frame: a key pressed and released between two frames is
// never seen, and two clicks within a frame are one. This queue keeps every event in order and hands ImGui
// at most one press/release transition per key and per mouse button per frame; an event that would be a
// second one waits, with everything after it, for the next frame. A short tap at 2 fps still counts exactly
// once, and a click lands where the mouse was when it happened.
class InputQueue {
public:
    void push(const InputEvent& event) { events_.push_back(event); }
    // Applies one frame's worth of events to `io`: call after the platform backend's NewFrame (which it
    // overrides for keys, buttons and, once known, the mouse position) and before ImGui::NewFrame.
    // Returns the number of events applied.
    std::size_t apply(ImGuiIO& io);
    std::size_t pending() const { return events_.size(); }

private:
    // False when the event must wait for the next frame.
    bool applyOne(const InputEvent& event, ImGuiIO& io);

    std::deque<InputEvent> events_;
    std::array<bool, 512> keys_{}; // ImGuiIO::KeysDown's size
    std::array<bool, 5> buttons_{};
    std::array<bool, 512> keyMoved_{}; // this frame
    std::array<bool, 5> buttonMoved_{};
    ImVec2 mouse_{0.0f, 0.0f};
    bool mouseKnown_ = false;
};

} // namespace dc::ui
