#pragma once

#include "base/expected.h"
#include "render/render_target.h"
#include "ui/frame_damage.h"

#include <imgui.h>

namespace dc::ui {

// Dear ImGui without a window: the OpenGL3 renderer draws every frame into an offscreen target. Used by the
// UI tests (input is injected through io()) and by `depthcloud bench render`. Needs a current GL context.
class HeadlessUi {
public:
    HeadlessUi() = default;
    ~HeadlessUi();
    HeadlessUi(const HeadlessUi&) = delete;
    HeadlessUi& operator=(const HeadlessUi&) = delete;

    Status init(int width, int height);
    // As a window resized: the next frame is laid out and drawn whole at the new size.
    Status resize(int width, int height);
    void newFrame(float deltaSeconds);
    // Finishes the ImGui frame and draws it into target().
    void render();
    // Finishes the ImGui frame and draws it, as the window does, only where the picture changes
    // (FrameDamage); returns whether it drew anything.
    bool renderIfChanged(std::uint64_t contentVersion);
    // Whether renderIfChanged() draws a frame that changed anywhere whole, as the window does where it swaps
    // (hardware GL), rather than in the parts that changed, as it does where it copies them (software GL).
    void setDrawsChangedFramesWhole(bool whole) { changedFramesWhole_ = whole; }

    ImGuiIO& io() { return ImGui::GetIO(); }
    const render::RenderTarget& target() const { return target_; }

private:
    ImGuiContext* context_ = nullptr;
    bool rendererReady_ = false;
    FrameDamage damage_;
    bool changedFramesWhole_ = false;
    render::RenderTarget target_{render::Sampling::Linear, render::DepthBuffer::Without}; // as a window's
};

} // namespace dc::ui
