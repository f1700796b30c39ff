#include "ui/panels.h"

namespace dc::ui {

void drawCameraPanel(const PanelImage& image, bool* open) {
    if (!ImGui::Begin(kCameraTitle, open)) {
        ImGui::End();
        return;
    }
    drawFittedImage(image, "No camera image yet.");
    ImGui::End();
}

} // namespace dc::ui
