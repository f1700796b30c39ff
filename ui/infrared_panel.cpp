#include "ui/image_panel.h"

namespace dc::ui {

PanelResult drawInfraredPanel(const PanelImage& image, const ProbeSource& probe, bool* open) {
    PanelResult result;
    if (!beginImagePanel(kInfraredTitle, open, result)) {
        ImGui::End();
        return result;
    }
    // The depth sensor's own view: its pixels are the depth map's, so the hover reads the depth there.
    interactWithImage(drawImage(image, ImageFit::Fit, "No infrared image yet."), probe, result);
    ImGui::End();
    return result;
}

} // namespace dc::ui
