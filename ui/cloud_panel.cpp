#include "ui/panels.h"

#include <cmath>
#include <cstdint>
#include <string>

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

// Anchors as dots with their number, measured segments as lines labelled at their middle.
void drawOverlay(const CloudOverlay& overlay, ImVec2 origin, ImVec2 size) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const auto at = [&](ImVec2 f) { return ImVec2(origin.x + f.x * size.x, origin.y + f.y * size.y); };
    const ImU32 line = IM_COL32(255, 214, 64, 255);
    for (const auto& [first, label] : overlay.segments) {
        const auto i = static_cast<std::size_t>(first);
        if (i + 1 >= overlay.anchors.size())
            continue;
        const ImVec2 a = at(overlay.anchors[i]);
        const ImVec2 b = at(overlay.anchors[i + 1]);
        draw->AddLine(a, b, line, 2.0f);
        const ImVec2 mid{(a.x + b.x) * 0.5f + 6.0f, (a.y + b.y) * 0.5f - 6.0f};
        draw->AddText(mid, IM_COL32(255, 255, 255, 255), label.c_str());
    }
    for (std::size_t i = 0; i < overlay.anchors.size(); ++i) {
        const ImVec2 p = at(overlay.anchors[i]);
        draw->AddCircle(p, 6.0f, line, 12, 2.0f);
        draw->AddText({p.x + 8.0f, p.y + 2.0f}, IM_COL32(255, 255, 255, 255), std::to_string(i + 1).c_str());
    }
    if (!overlay.summary.empty())
        draw->AddText({origin.x + 12.0f, origin.y + size.y - ImGui::GetTextLineHeight() - 8.0f},
                      IM_COL32(255, 255, 255, 255), overlay.summary.c_str());
}

// The mouse over the view in cloud-image pixels, and whether the left button was clicked (released
// without dragging) there.
void readPointer(CloudPanelResult& result, ImVec2 origin, ImVec2 size) {
    const ImGuiIO& io = ImGui::GetIO();
    if (!ImGui::IsItemHovered())
        return;
    const ImVec2 at{io.MousePos.x - origin.x, io.MousePos.y - origin.y};
    result.hoverPixels = at;
    constexpr float kClickSlopPixels = 3.0f;
    // The release that ends a double-click (a view reset) is not a click of its own.
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseClickedLastCount[ImGuiMouseButton_Left] < 2 &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] <= kClickSlopPixels * kClickSlopPixels &&
        at.x >= 0.0f && at.y >= 0.0f && at.x < size.x && at.y < size.y)
        result.clickPixels = at;
    result.doubleClicked = ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left);
}

} // namespace

CloudPanelResult drawCloudPanel(const PanelImage& image, CloudSettings& cloud, const CloudOverlay& overlay,
                                const std::string& message, bool zoomed, bool* open) {
    CloudPanelResult result;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0.0f, 0.0f));
    result.panel.visible = ImGui::Begin(kCloudTitle, open);
    ImGui::PopStyleVar();
    result.panel.windowPos = ImGui::GetWindowPos();
    result.panel.windowSize = ImGui::GetWindowSize();
    if (!result.panel.visible) {
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
        ImGui::SetItemAllowOverlap(); // the zoom button drawn over the view must still take clicks
        result.viewChanged = applyMouse(cloud);
        readPointer(result, origin, avail);
        if (!image.empty()) {
            ImGui::GetWindowDrawList()->AddImage(
                reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)), origin,
                {origin.x + avail.x, origin.y + avail.y}, kFlippedUv0, kFlippedUv1);
        }
        drawOverlay(overlay, origin, avail);
        ImGui::SetCursorScreenPos(
            {origin.x + avail.x - ImGui::CalcTextSize("Restore").x - 24.0f, origin.y + 8.0f});
        result.panel.toggleZoom = ImGui::SmallButton(zoomed ? "Restore" : "Zoom");
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
