#include "ui/image_panel.h"

namespace dc::ui {

CameraPanelResult drawCameraPanel(const PanelImage& image, const PanelImage& depthOverlay,
                                  const CameraView& view, const ProbeSource& probe, bool* open) {
    CameraPanelResult result;
    if (!beginImagePanel(kCameraTitle, open, result.panel)) {
        ImGui::End();
        return result;
    }
    const ImageRect shown =
        drawImage(image, view.fill ? ImageFit::Fill : ImageFit::Fit, "No camera image yet.");
    if (view.depthOverlay)
        drawOverlay(depthOverlay, shown, view.overlayOpacity);
    interactWithImage(shown, probe, result.panel);
    ImGui::End();
    // The whole image's width on screen: a filled panel shows a crop of a wider image.
    const float visible = shown.visibleMax.x - shown.visibleMin.x;
    result.shownWidth = visible > 0.0f ? static_cast<int>((shown.max.x - shown.min.x) / visible) : 0;
    return result;
}

} // namespace dc::ui
