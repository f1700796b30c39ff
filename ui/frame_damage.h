#pragma once

#include "render/render_target.h"

#include <imgui.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc::ui {

// A rectangle of framebuffer pixels, top-left origin, x1 and y1 excluded.
struct DamageRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    bool operator==(const DamageRect&) const = default;
};

// The same pixels GL's way (bottom-left origin), in a framebuffer `height` pixels tall.
inline render::PixelRect pixelRectOf(const DamageRect& r, int height) {
    return {r.x0, height - r.y1, r.x1 - r.x0, r.y1 - r.y0};
}

// Where a finished ImGui frame would put other pixels on the screen than the frame composited before it.
// A window (draw list) whose vertices, indices and commands are the same, over textures whose contents did
// not change, draws the same pixels; so only the windows that changed, and the images whose textures got
// new contents, are drawn again, and a frame that changes nothing is not drawn at all. On software GL the
// composite is most of a frame's cost: a paused replay would pay it at the display's rate for nothing,
// and a new camera frame changes the images, not the controls around them.
class FrameDamage {
public:
    // The rectangles where `data` differs from the frame passed last: none when it shows the same picture,
    // the whole framebuffer after forget(), or when windows changed their order or the display its size.
    // `contentVersion` is ViewRenderer::contentVersion(): when it moved, every command that samples another
    // texture than `fontTexture`, or calls back (the cloud's copy), is drawn again.
    std::vector<DamageRect> update(const ImDrawData& data, std::uint64_t contentVersion,
                                   ImTextureID fontTexture);
    // The picture is lost (the window was exposed, or is new): the next frame is drawn whole.
    void forget() { lists_.clear(); }

private:
    struct List {
        std::string owner;
        std::vector<std::byte> bytes;    // vertices, indices and commands, field by field (no padding)
        DamageRect bounds;               // every pixel its commands may touch
        std::vector<DamageRect> content; // where it shows textures other than the font, or calls back
    };
    static std::vector<List> describe(const ImDrawData& data, ImTextureID fontTexture);
    std::optional<std::vector<DamageRect>> changes(const std::vector<List>& lists,
                                                   std::uint64_t contentVersion) const;
    std::vector<List> lists_;
    ImVec2 displayPos_, displaySize_, framebufferScale_;
    std::uint64_t contentVersion_ = 0;
};

// Rounds every command's clip rectangle to the framebuffer pixels the OpenGL3 backend scissors it to (it
// truncates), so that a clip cut to a damage rectangle scissors exactly the pixels of both. Leaves them
// as they are where the framebuffer scale is not a whole number, which such a cut could not keep exact.
void snapClipRects(ImDrawData& data);

// Draws `data` only within `rects`: `clear` is called for each first, then every command with its clip
// cut to the rectangle. The drawing within each is the drawing of the whole frame (after snapClipRects).
template <class Clear>
void drawDamaged(ImDrawData& data, const std::vector<DamageRect>& rects, Clear&& clear);

// The OpenGL3 backend's drawing of `data` with every clip rectangle cut to `rect`.
void drawWithin(ImDrawData& data, const DamageRect& rect);

template <class Clear>
void drawDamaged(ImDrawData& data, const std::vector<DamageRect>& rects, Clear&& clear) {
    for (const DamageRect& rect : rects) {
        clear(rect);
        drawWithin(data, rect);
    }
}

} // namespace dc::ui
