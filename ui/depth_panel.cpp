#include "render/colormap.h"
#include "ui/image_panel.h"

#include <algorithm>
#include <cstdio>

namespace dc::ui {

namespace {

// The colormap drawn as a strip of linear segments (exact: the maps are piecewise linear over their
// stops), with the range at its ends.
void drawLegend(const DepthLegend& legend) {
    constexpr int kSegments = render::kColormapStopCount - 1;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = ImGui::GetTextLineHeight() * 0.6f;
    const auto& stops = render::colormapStops(legend.colormap);
    for (int i = 0; i < kSegments; ++i) {
        const auto& a = stops[static_cast<std::size_t>(i)];
        const auto& b = stops[static_cast<std::size_t>(i) + 1];
        const ImU32 ca = ImGui::GetColorU32(ImVec4(a[0], a[1], a[2], 1.0f));
        const ImU32 cb = ImGui::GetColorU32(ImVec4(b[0], b[1], b[2], 1.0f));
        const float x0 = p.x + width * static_cast<float>(i) / kSegments;
        const float x1 = p.x + width * static_cast<float>(i + 1) / kSegments;
        draw->AddRectFilledMultiColor({x0, p.y}, {x1, p.y + height}, ca, cb, cb, ca);
    }
    ImGui::Dummy({width, height});
    ImGui::Text("%.2f m", legend.minMeters);
    char text[48];
    std::snprintf(text, sizeof text, "%s%s  %.2f m", render::toString(legend.colormap),
                  legend.automatic ? ", auto" : "", legend.maxMeters);
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(text).x));
    ImGui::TextUnformatted(text);
}

} // namespace

PanelResult drawDepthPanel(const PanelImage& image, const PanelOverlay& colour, const DepthLegend& legend,
                           const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                           const SourceTabs& tabs) {
    PanelResult result;
    if (!beginImagePanel(kDepthTitle, open, result)) {
        endImagePanel({});
        return result;
    }
    drawSourceTabs(tabs);
    const float legendHeight = ImGui::GetTextLineHeight() * 0.6f + ImGui::GetTextLineHeightWithSpacing() +
                               ImGui::GetStyle().ItemSpacing.y * 2.0f;
    ImageRect shown;
    if (ImGui::BeginChild("##depth", ImVec2(0.0f, -legendHeight))) {
        shown = drawImage(image, ImageFit::Fit, "No depth yet.");
        drawOverlay(colour.image, shown, colour.opacity);
        interactWithImage(shown, probe, result, roi);
    }
    ImGui::EndChild();
    drawLegend(legend);
    endImagePanel(shown);
    return result;
}

} // namespace dc::ui
