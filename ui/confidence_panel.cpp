#include "ui/panels.h"

namespace dc::ui {

namespace {

void legendEntry(const char* label, ImVec4 color) {
    ImGui::ColorButton(label, color, ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                       ImVec2(ImGui::GetTextLineHeight(), ImGui::GetTextLineHeight()));
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}

} // namespace

void drawConfidencePanel(const PanelImage& image, bool available, bool* open) {
    if (!ImGui::Begin(kConfidenceTitle, open)) {
        ImGui::End();
        return;
    }
    if (!available) {
        ImGui::TextWrapped("This source provides no confidence: every depth sample is treated as high.");
        ImGui::End();
        return;
    }
    const float legendHeight = ImGui::GetFrameHeightWithSpacing();
    if (ImGui::BeginChild("##confidence", ImVec2(0.0f, -legendHeight)))
        drawFittedImage(image, "No confidence yet.");
    ImGui::EndChild();
    legendEntry("low", ImVec4(1, 0, 0, 1));
    ImGui::SameLine();
    legendEntry("medium", ImVec4(0, 1, 0, 1));
    ImGui::SameLine();
    legendEntry("high", ImVec4(0, 0, 1, 1));
    ImGui::End();
}

} // namespace dc::ui
