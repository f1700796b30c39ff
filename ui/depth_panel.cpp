#include "render/colormap.h"
#include "ui/panels.h"

#include <algorithm>
#include <cstdio>

namespace dc::ui {

namespace {

// The jet ramp drawn as a strip of linear segments, with the range at its ends.
void drawLegend(const DepthRange& range) {
    constexpr int kSegments = 32;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = ImGui::GetTextLineHeight() * 0.6f;
    for (int i = 0; i < kSegments; ++i) {
        const auto a = render::jetColor(static_cast<float>(i) / kSegments);
        const auto b = render::jetColor(static_cast<float>(i + 1) / kSegments);
        const ImU32 ca = ImGui::GetColorU32(ImVec4(a[0], a[1], a[2], 1.0f));
        const ImU32 cb = ImGui::GetColorU32(ImVec4(b[0], b[1], b[2], 1.0f));
        const float x0 = p.x + width * static_cast<float>(i) / kSegments;
        const float x1 = p.x + width * static_cast<float>(i + 1) / kSegments;
        draw->AddRectFilledMultiColor({x0, p.y}, {x1, p.y + height}, ca, cb, cb, ca);
    }
    ImGui::Dummy({width, height});
    ImGui::Text("%.2f m", range.minMeters);
    char text[32];
    std::snprintf(text, sizeof text, "%.2f m", range.maxMeters);
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(text).x));
    ImGui::TextUnformatted(text);
}

} // namespace

void drawDepthPanel(const PanelImage& image, const DepthRange& range, bool* open) {
    if (!ImGui::Begin(kDepthTitle, open)) {
        ImGui::End();
        return;
    }
    const float legendHeight = ImGui::GetTextLineHeight() * 0.6f + ImGui::GetTextLineHeightWithSpacing() +
                               ImGui::GetStyle().ItemSpacing.y * 2.0f;
    if (ImGui::BeginChild("##depth", ImVec2(0.0f, -legendHeight)))
        drawFittedImage(image, "No depth yet.");
    ImGui::EndChild();
    drawLegend(range);
    ImGui::End();
}

} // namespace dc::ui
