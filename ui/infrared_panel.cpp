#include "ui/image_panel.h"

#include <algorithm>
#include <cstdio>

namespace dc::ui {

namespace {

// The stretch as a black-to-white strip with the raw intensities at its ends: what the gray levels mean.
void drawStretchLegend(const processing::IntensityRange& range) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = ImGui::GetTextLineHeight() * 0.6f;
    draw->AddRectFilledMultiColor(p, {p.x + width, p.y + height}, IM_COL32_BLACK, IM_COL32_WHITE,
                                  IM_COL32_WHITE, IM_COL32_BLACK);
    ImGui::Dummy({width, height});
    ImGui::Text("raw %u", static_cast<unsigned>(range.low));
    char text[64];
    std::snprintf(text, sizeof text, "1st-99th percentile  raw %u", static_cast<unsigned>(range.high));
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(text).x));
    ImGui::TextUnformatted(text);
}

} // namespace

PanelResult drawInfraredPanel(const PanelImage& image, const processing::IntensityRange& range,
                              const ProbeSource& probe, const RoiOverlay& roi, bool* open) {
    PanelResult result;
    if (!beginImagePanel(kInfraredTitle, open, result)) {
        endImagePanel({});
        return result;
    }
    const float legendHeight = ImGui::GetTextLineHeight() * 0.6f + ImGui::GetTextLineHeightWithSpacing() +
                               ImGui::GetStyle().ItemSpacing.y * 2.0f;
    ImageRect shown;
    if (ImGui::BeginChild("##infrared", ImVec2(0.0f, -legendHeight))) {
        // The depth sensor's own view: its pixels are the depth map's, so the hover reads the depth (and
        // the raw intensity) there.
        shown = drawImage(image, ImageFit::Fit, "No infrared image yet.");
        interactWithImage(shown, probe, result, roi);
    }
    ImGui::EndChild();
    drawStretchLegend(range);
    endImagePanel(shown);
    return result;
}

} // namespace dc::ui
