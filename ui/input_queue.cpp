#include "ui/input_queue.h"

// For the modifier keys' codes only: the queue's key codes are GLFW's, as the ImGui backend's are.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

namespace dc::ui {

namespace {

template <std::size_t N> bool inRange(int code, const std::array<bool, N>&) {
    return code >= 0 && static_cast<std::size_t>(code) < N;
}

} // namespace

bool InputQueue::applyOne(const InputEvent& e, ImGuiIO& io) {
    switch (e.kind) {
    case InputEvent::Kind::Key:
        if (!inRange(e.code, keys_) || keys_[e.code] == e.down)
            return true; // not a transition: nothing to hand over
        if (keyMoved_[e.code])
            return false;
        keys_[e.code] = e.down;
        keyMoved_[e.code] = true;
        return true;
    case InputEvent::Kind::MouseButton:
        if (!inRange(e.code, buttons_) || buttons_[e.code] == e.down)
            return true;
        if (buttonMoved_[e.code])
            return false;
        buttons_[e.code] = e.down;
        buttonMoved_[e.code] = true;
        return true;
    case InputEvent::Kind::Char:
        io.AddInputCharacter(static_cast<unsigned>(e.code));
        return true;
    case InputEvent::Kind::CursorPos:
        mouse_ = {e.x, e.y};
        mouseKnown_ = true;
        return true;
    case InputEvent::Kind::Scroll:
        io.MouseWheelH += e.x;
        io.MouseWheel += e.y;
        return true;
    }
    return true;
}

std::size_t InputQueue::apply(ImGuiIO& io) {
    keyMoved_.fill(false);
    buttonMoved_.fill(false);
    std::size_t applied = 0;
    while (!events_.empty() && applyOne(events_.front(), io)) {
        events_.pop_front();
        ++applied;
    }
    std::copy(keys_.begin(), keys_.end(), io.KeysDown);
    std::copy(buttons_.begin(), buttons_.end(), io.MouseDown);
    // The backend's position is where the mouse is now; while events wait, ImGui must see where it was.
    if (mouseKnown_ && (applied > 0 || !events_.empty() || io.MousePos.x > -FLT_MAX * 0.5f))
        io.MousePos = mouse_;
    io.KeyCtrl = keys_[GLFW_KEY_LEFT_CONTROL] || keys_[GLFW_KEY_RIGHT_CONTROL];
    io.KeyShift = keys_[GLFW_KEY_LEFT_SHIFT] || keys_[GLFW_KEY_RIGHT_SHIFT];
    io.KeyAlt = keys_[GLFW_KEY_LEFT_ALT] || keys_[GLFW_KEY_RIGHT_ALT];
    io.KeySuper = keys_[GLFW_KEY_LEFT_SUPER] || keys_[GLFW_KEY_RIGHT_SUPER];
    return applied;
}

} // namespace dc::ui
