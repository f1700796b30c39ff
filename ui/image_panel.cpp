#include "ui/image_panel.h"

namespace dc::ui {

bool beginImagePanel(const char* title, bool* open, PanelResult& result) {
    result.visible = ImGui::Begin(title, open);
    result.windowPos = ImGui::GetWindowPos();
    result.windowSize = ImGui::GetWindowSize();
    return result.visible;
}

void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result) {
    const float visible = shown.visibleMax.x - shown.visibleMin.x;
    result.shownWidth = visible > 0.0f ? static_cast<int>((shown.max.x - shown.min.x) / visible) : 0;
    const std::optional<ImVec2> at = imageFractionUnderMouse(shown);
    if (!at)
        return;
    result.probe = probeAtFraction(source, *at);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left))
        result.toggleZoom = true;
}

} // namespace dc::ui
