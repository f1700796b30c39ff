#include "ui/panels.h"

#include <cmath>
#include <cstdint>

namespace dc::ui {

namespace {
constexpr float kOrbitRadiansPerPixel = 0.008f;
constexpr float kPanMetersPerPixel = 0.002f;
constexpr float kZoomPerWheelStep = 1.1f;

bool applyMouse(CloudSettings& cloud) {
    const ImGuiIO& io = ImGui::GetIO();
    bool changed = false;
    if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0.0f)) {
        cloud.orbit.yawRadians += io.MouseDelta.x * kOrbitRadiansPerPixel;
        cloud.orbit.pitchRadians += io.MouseDelta.y * kOrbitRadiansPerPixel;
        changed = true;
    }
    if (ImGui::IsItemActive() && (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 0.0f) ||
                                  ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 0.0f))) {
        cloud.orbit.panMeters.x += io.MouseDelta.x * kPanMetersPerPixel;
        cloud.orbit.panMeters.y -= io.MouseDelta.y * kPanMetersPerPixel;
        changed = true;
    }
    if (ImGui::IsItemHovered() && io.MouseWheel != 0.0f) {
        cloud.orbit.zoom *= std::pow(kZoomPerWheelStep, io.MouseWheel);
        changed = true;
    }
    if (ImGui::IsItemHovered() && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) {
        cloud.orbit = {};
        changed = true;
    }
    if (changed)
        sanitize(cloud);
    return changed;
}

} // namespace

CloudPanelResult drawCloudPanel(const PanelImage& image, CloudSettings& cloud, const std::string& message,
                                bool* open) {
    CloudPanelResult result;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0.0f, 0.0f));
    const bool visible = ImGui::Begin(kCloudTitle, open);
    ImGui::PopStyleVar();
    if (!visible) {
        ImGui::End();
        return result;
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    result.wantedWidth = static_cast<int>(avail.x);
    result.wantedHeight = static_cast<int>(avail.y);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    if (avail.x >= 1.0f && avail.y >= 1.0f) {
        // One button over the whole view takes the mouse, so dragging the cloud never moves the window.
        ImGui::InvisibleButton("##cloud", avail,
                               ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                                   ImGuiButtonFlags_MouseButtonMiddle);
        result.viewChanged = applyMouse(cloud);
        if (!image.empty()) {
            ImGui::GetWindowDrawList()->AddImage(
                reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)), origin,
                {origin.x + avail.x, origin.y + avail.y}, kFlippedUv0, kFlippedUv1);
        }
    }
    if (!message.empty()) {
        ImGui::SetCursorScreenPos({origin.x + 12.0f, origin.y + 12.0f});
        ImGui::PushTextWrapPos(origin.x + avail.x - 12.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.4f, 1.0f), "%s", message.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
    return result;
}

} // namespace dc::ui
