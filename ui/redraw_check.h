#pragma once

#include <imgui.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dc::ui {

// Whether a finished ImGui frame would put other pixels on the screen than the frame drawn last. The
// same draw lists over textures whose contents did not change make the same picture, so a window whose
// picture did not change keeps the one it shows: on software GL the composite is most of a frame's cost,
// and a paused replay would otherwise pay it at the display's rate for nothing.
class RedrawCheck {
public:
    // Whether drawing `data` now changes the picture: its draw lists differ from the last drawn, or
    // `contentVersion` (ViewRenderer::contentVersion(), which counts every change to what the textures
    // hold) moved since. A frame that does is remembered as the one drawn.
    bool needed(const ImDrawData& data, std::uint64_t contentVersion);
    // The window lost its picture (exposed, or its buffer is undefined): the next frame is drawn.
    void forget() { drawn_.clear(); }

private:
    std::vector<std::byte> drawn_; // the last drawn frame's lists, field by field (no padding)
    std::vector<std::byte> next_;
};

} // namespace dc::ui
