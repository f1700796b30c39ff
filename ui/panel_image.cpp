#include "ui/panel_image.h"

#include <algorithm>
#include <cstdint>

namespace dc::ui {

namespace {

ImTextureID textureOf(const PanelImage& image) {
    return reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId));
}

// Texture coordinates of a visible part of the image, upright either way.
ImVec2 uvOf(const PanelImage& image, ImVec2 fraction) {
    return image.bottomUp ? ImVec2(fraction.x, 1.0f - fraction.y) : fraction;
}

} // namespace

ImageRect drawImage(const PanelImage& image, ImageFit fit, const char* emptyMessage) {
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    if (image.empty() || avail.x < 1.0f || avail.y < 1.0f) {
        ImGui::TextWrapped("%s", emptyMessage);
        return {origin, origin};
    }
    const float sx = avail.x / static_cast<float>(image.width);
    const float sy = avail.y / static_cast<float>(image.height);
    const float scale = fit == ImageFit::Fit ? std::min(sx, sy) : std::max(sx, sy);
    const ImVec2 size{static_cast<float>(image.width) * scale, static_cast<float>(image.height) * scale};
    ImageRect shown;
    if (fit == ImageFit::Fit) {
        shown.min = {origin.x + (avail.x - size.x) * 0.5f, origin.y + (avail.y - size.y) * 0.5f};
        shown.max = {shown.min.x + size.x, shown.min.y + size.y};
    } else {
        shown.min = origin;
        shown.max = {origin.x + avail.x, origin.y + avail.y};
        const ImVec2 crop{(1.0f - avail.x / size.x) * 0.5f, (1.0f - avail.y / size.y) * 0.5f};
        shown.visibleMin = crop;
        shown.visibleMax = {1.0f - crop.x, 1.0f - crop.y};
    }
    ImGui::SetCursorScreenPos(shown.min);
    ImGui::Image(textureOf(image), {shown.max.x - shown.min.x, shown.max.y - shown.min.y},
                 uvOf(image, shown.visibleMin), uvOf(image, shown.visibleMax));
    return shown;
}

void drawOverlay(const PanelImage& overlay, const ImageRect& shown, float opacity) {
    if (overlay.empty() || shown.max.x <= shown.min.x)
        return;
    const ImU32 tint = ImGui::GetColorU32(ImVec4(1.0f, 1.0f, 1.0f, opacity));
    ImGui::GetWindowDrawList()->AddImage(textureOf(overlay), shown.min, shown.max,
                                         uvOf(overlay, shown.visibleMin), uvOf(overlay, shown.visibleMax),
                                         tint);
}

void drawOverlayAt(const PanelImage& overlay, const ImageRect& shown, ImVec4 fractions, float opacity) {
    if (overlay.empty() || shown.max.x <= shown.min.x)
        return;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(shown.min, shown.max, true);
    draw->AddImage(textureOf(overlay), screenAtFraction(shown, {fractions.x, fractions.y}),
                   screenAtFraction(shown, {fractions.z, fractions.w}), uvOf(overlay, {0.0f, 0.0f}),
                   uvOf(overlay, {1.0f, 1.0f}), ImGui::GetColorU32(ImVec4(1.0f, 1.0f, 1.0f, opacity)));
    draw->PopClipRect();
}

std::optional<ImVec2> imageFractionUnderMouse(const ImageRect& shown) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    if (!ImGui::IsWindowHovered() || m.x < shown.min.x || m.y < shown.min.y || m.x >= shown.max.x ||
        m.y >= shown.max.y)
        return std::nullopt;
    return imageFractionAt(shown, m);
}

ImVec2 imageFractionAt(const ImageRect& shown, ImVec2 screen) {
    const float fx =
        std::clamp((screen.x - shown.min.x) / std::max(shown.max.x - shown.min.x, 1.0f), 0.0f, 1.0f);
    const float fy =
        std::clamp((screen.y - shown.min.y) / std::max(shown.max.y - shown.min.y, 1.0f), 0.0f, 1.0f);
    return ImVec2(shown.visibleMin.x + fx * (shown.visibleMax.x - shown.visibleMin.x),
                  shown.visibleMin.y + fy * (shown.visibleMax.y - shown.visibleMin.y));
}

ImVec2 screenAtFraction(const ImageRect& shown, ImVec2 fraction) {
    const ImVec2 visible{shown.visibleMax.x - shown.visibleMin.x, shown.visibleMax.y - shown.visibleMin.y};
    return ImVec2(shown.min.x + (fraction.x - shown.visibleMin.x) / visible.x * (shown.max.x - shown.min.x),
                  shown.min.y + (fraction.y - shown.visibleMin.y) / visible.y * (shown.max.y - shown.min.y));
}

} // namespace dc::ui
