#include "ui/panel_image.h"

#include <algorithm>
#include <cstdint>

namespace dc::ui {

ImageRect drawFittedImage(const PanelImage& image, const char* emptyMessage) {
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    if (image.empty() || avail.x < 1.0f || avail.y < 1.0f) {
        ImGui::TextWrapped("%s", emptyMessage);
        return {origin, origin};
    }
    const float scale =
        std::min(avail.x / static_cast<float>(image.width), avail.y / static_cast<float>(image.height));
    const ImVec2 size{static_cast<float>(image.width) * scale, static_cast<float>(image.height) * scale};
    const ImVec2 offset{(avail.x - size.x) * 0.5f, (avail.y - size.y) * 0.5f};
    ImGui::SetCursorScreenPos({origin.x + offset.x, origin.y + offset.y});
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)), size,
                 kFlippedUv0, kFlippedUv1);
    const ImVec2 min{origin.x + offset.x, origin.y + offset.y};
    return {min, {min.x + size.x, min.y + size.y}};
}

} // namespace dc::ui
