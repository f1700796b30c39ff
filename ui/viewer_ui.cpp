#include "ui/viewer.h"

#include <algorithm>

namespace dc::ui {

namespace {

// First-run placement (the saved layout wins afterwards): controls on the left, the cloud in the middle,
// depth, confidence and camera stacked on the right, all above the status bar.
struct Layout {
    ImVec2 origin;
    ImVec2 size;
    float leftWidth;
    float rightWidth;
};

Layout defaultLayout(float statusHeight) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const ImVec2 size{vp->WorkSize.x, std::max(vp->WorkSize.y - statusHeight, 1.0f)};
    return {vp->WorkPos, size, std::clamp(size.x * 0.23f, 220.0f, 340.0f), size.x * 0.27f};
}

void place(const Layout& l, float x, float y, float w, float h) {
    ImGui::SetNextWindowPos({l.origin.x + x, l.origin.y + y}, ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize({w, h}, ImGuiCond_FirstUseEver);
}

PanelImage imageOf(const render::RenderTarget& target) {
    return {target.colorTexture(), target.width(), target.height()};
}

} // namespace

void Viewer::drawUi() {
    handleShortcuts(settings_);
    const float statusHeight = drawStatusBar(statusLine());
    const Layout l = defaultLayout(statusHeight);
    const float cloudWidth = l.size.x - l.leftWidth - l.rightWidth;
    const float third = l.size.y / 3.0f;
    PanelVisibility& show = settings_.panels;

    if (show.controls) {
        place(l, 0, 0, l.leftWidth, l.size.y);
        const ControlsContext context{pipeline_.hasStage(processing::kSmoothingStage),
                                      pipeline_.hasStage(processing::kUpsamplingStage)};
        drawControlsPanel(settings_, context, &show.controls);
    }
    if (show.cloud) {
        place(l, l.leftWidth, 0, cloudWidth, l.size.y);
        const std::string message = sourceRunning_ ? std::string() : sourceMessage_;
        const CloudPanelResult r =
            drawCloudPanel(imageOf(cloudTarget_), settings_.cloud, message, &show.cloud);
        if (r.wantedWidth > 0 && r.wantedHeight > 0 &&
            (r.wantedWidth != cloudTarget_.width() || r.wantedHeight != cloudTarget_.height()))
            resizeCloud(r.wantedWidth, r.wantedHeight);
    }
    const float right = l.size.x - l.rightWidth;
    if (show.depth) {
        place(l, right, 0, l.rightWidth, third);
        drawDepthPanel(imageOf(depthTarget_), settings_.depthRange, &show.depth);
    }
    if (show.confidence) {
        place(l, right, third, l.rightWidth, third);
        drawConfidencePanel(imageOf(confidenceTarget_), session_.capabilities().confidence, &show.confidence);
    }
    if (show.camera) {
        place(l, right, 2.0f * third, l.rightWidth, third);
        const int shownWidth = drawCameraPanel(imageOf(cameraTarget_), &show.camera);
        if (shownWidth > 0)
            cameraShownWidth_ = shownWidth;
    }
}

} // namespace dc::ui
