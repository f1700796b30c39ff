#include "ui/panels.h"

namespace dc::ui {

int drawCameraPanel(const PanelImage& image, bool* open) {
    if (!ImGui::Begin(kCameraTitle, open)) {
        ImGui::End();
        return 0;
    }
    const ImageRect shown = drawFittedImage(image, "No camera image yet.");
    ImGui::End();
    return static_cast<int>(shown.max.x - shown.min.x);
}

} // namespace dc::ui
