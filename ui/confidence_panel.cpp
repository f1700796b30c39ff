#include "ui/image_panel.h"

namespace dc::ui {

namespace {

void legendEntry(const char* label, ImVec4 color) {
    ImGui::ColorButton(label, color, ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                       ImVec2(ImGui::GetTextLineHeight(), ImGui::GetTextLineHeight()));
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}

} // namespace

PanelResult drawConfidencePanel(const PanelImage& image, bool available, bool estimated,
                                const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                                const SourceTabs& tabs) {
    PanelResult result;
    if (!beginImagePanel(kConfidenceTitle, open, result)) {
        endImagePanel({});
        return result;
    }
    drawSourceTabs(tabs);
    if (!available) {
        ImGui::TextWrapped("This source provides no confidence: every depth sample is treated as high.");
        endImagePanel({});
        return result;
    }
    const float legendHeight = ImGui::GetFrameHeightWithSpacing();
    ImageRect shown;
    if (ImGui::BeginChild("##confidence", ImVec2(0.0f, -legendHeight))) {
        shown = drawImage(image, ImageFit::Fit, "No confidence yet.");
        interactWithImage(shown, probe, result, roi);
    }
    ImGui::EndChild();
    legendEntry("low", ImVec4(1, 0, 0, 1));
    ImGui::SameLine();
    legendEntry("medium", ImVec4(0, 1, 0, 1));
    ImGui::SameLine();
    legendEntry("high", ImVec4(0, 0, 1, 1));
    if (estimated) {
        ImGui::SameLine();
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "estimated");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("The camera reports none: estimated from holes, local variance and stability.");
    }
    endImagePanel(shown);
    return result;
}

} // namespace dc::ui
