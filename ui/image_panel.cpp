#include "ui/image_panel.h"

namespace dc::ui {

bool beginImagePanel(const char* title, bool* open, PanelResult& result) {
    result.visible = ImGui::Begin(title, open);
    result.windowPos = ImGui::GetWindowPos();
    result.windowSize = ImGui::GetWindowSize();
    return result.visible;
}

void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result) {
    const std::optional<ImVec2> at = imageFractionUnderMouse(shown);
    if (!at)
        return;
    result.probe = probeAtFraction(source, *at);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left))
        result.toggleZoom = true;
}

} // namespace dc::ui
