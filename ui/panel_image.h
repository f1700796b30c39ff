#pragma once

#include <imgui.h>

#include <optional>

namespace dc::ui {

// A panel's content as a GL texture made by render/, with its size in pixels. Render targets hold their
// rows bottom-up (OpenGL); images uploaded from the CPU top-down.
struct PanelImage {
    unsigned textureId = 0;
    int width = 0;
    int height = 0;
    bool bottomUp = true;

    bool empty() const { return textureId == 0 || width <= 0 || height <= 0; }
};

// Where an image landed on screen (min, max) and which part of it is visible there: fractions of the
// image, (0, 0) at its top-left corner. A fitted image shows all of it; a filling one is cropped.
struct ImageRect {
    ImVec2 min;
    ImVec2 max;
    ImVec2 visibleMin{0.0f, 0.0f};
    ImVec2 visibleMax{1.0f, 1.0f};
};

enum class ImageFit {
    Fit,  // as large as fits, aspect kept, centred (letterboxed)
    Fill, // covers the region, aspect kept, cropped evenly (the sample's aspect-fill display transform)
};

// Draws `image` into the remaining content region. An empty image draws `emptyMessage` instead and
// returns an empty rectangle at the cursor.
ImageRect drawImage(const PanelImage& image, ImageFit fit, const char* emptyMessage);

// Draws `overlay` over exactly the part of the image `shown` covers, at the given opacity.
void drawOverlay(const PanelImage& overlay, const ImageRect& shown, float opacity);

// Draws `overlay` stretched over the part `fractions` (left, top, right, bottom) of the image, clipped to
// what `shown` shows of it.
void drawOverlayAt(const PanelImage& overlay, const ImageRect& shown, ImVec4 fractions, float opacity);

// Where the mouse is over a drawn image, as a fraction of the whole image; nothing when it is elsewhere or
// the window is not hovered.
std::optional<ImVec2> imageFractionUnderMouse(const ImageRect& shown);

// A point on screen as a fraction of the whole image, clamped to the part shown.
ImVec2 imageFractionAt(const ImageRect& shown, ImVec2 screen);
// A fraction of the whole image as a point on screen (outside the shown part where it is cropped away).
ImVec2 screenAtFraction(const ImageRect& shown, ImVec2 fraction);

// Render targets are stored bottom-up (OpenGL), ImGui draws top-down: these UVs flip them upright.
inline const ImVec2 kFlippedUv0{0.0f, 1.0f};
inline const ImVec2 kFlippedUv1{1.0f, 0.0f};

} // namespace dc::ui
