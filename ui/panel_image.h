#pragma once

#include <imgui.h>

namespace dc::ui {

// A panel's content rendered into a GL texture by render/, with its size in pixels.
struct PanelImage {
    unsigned textureId = 0;
    int width = 0;
    int height = 0;

    bool empty() const { return textureId == 0 || width <= 0 || height <= 0; }
};

// Draws `image` as large as the remaining content region allows, keeping its aspect ratio, centred.
// Returns the screen rectangle it occupies (min, max); an empty image draws `emptyMessage` instead.
struct ImageRect {
    ImVec2 min;
    ImVec2 max;
};
ImageRect drawFittedImage(const PanelImage& image, const char* emptyMessage);

// Render targets are stored bottom-up (OpenGL), ImGui draws top-down: these UVs flip them upright.
inline const ImVec2 kFlippedUv0{0.0f, 1.0f};
inline const ImVec2 kFlippedUv1{1.0f, 0.0f};

} // namespace dc::ui
