#include "ui/image_panel.h"

namespace dc::ui {

PanelResult drawCameraPanel(const PanelImage& image, const PanelImage& depthOverlay, const CameraView& view,
                            const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                            const SourceTabs& tabs) {
    PanelResult result;
    if (!beginImagePanel(kCameraTitle, open, result)) {
        endImagePanel({});
        return result;
    }
    drawSourceTabs(tabs);
    const ImageRect shown =
        drawImage(image, view.fill ? ImageFit::Fill : ImageFit::Fit, "No camera image yet.");
    if (view.depthOverlay)
        drawOverlay(depthOverlay, shown, view.overlayOpacity);
    interactWithImage(shown, probe, result, roi);
    endImagePanel(shown);
    return result;
}

} // namespace dc::ui
