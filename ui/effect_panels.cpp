#include "ui/image_panel.h"

#include <algorithm>
#include <cstdint>

namespace dc::ui {

namespace {

// An upright CPU-made image (no flip, unlike render targets), fitted to what remains of the panel.
void drawEffectImage(const PanelImage& image, const char* emptyMessage) {
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    if (image.empty() || avail.x < 1.0f || avail.y < 1.0f) {
        ImGui::TextWrapped("%s", emptyMessage);
        return;
    }
    const float scale =
        std::min(avail.x / static_cast<float>(image.width), avail.y / static_cast<float>(image.height));
    const ImVec2 size{static_cast<float>(image.width) * scale, static_cast<float>(image.height) * scale};
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::SetCursorScreenPos({origin.x + (avail.x - size.x) * 0.5f, origin.y + (avail.y - size.y) * 0.5f});
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)), size);
}

} // namespace

bool drawFogPanel(const PanelImage& image, processing::FogSettings& fog, bool* open) {
    if (!ImGui::Begin(kFogTitle, open)) {
        ImGui::End();
        return false;
    }
    ImGui::PushItemWidth(ImGui::GetFontSize() * 8.0f);
    bool changed = ImGui::SliderFloat("Fog max", &fog.fogMaxMeters, 0.5f, 10.0f, "%.1f m");
    ImGui::SameLine();
    // The sample's Gaussian blur of the depth before the fog (sigma 5): softer fog edges at depth steps.
    changed |= ImGui::SliderFloat("Blur", &fog.blurSigmaPixels, 0.0f, 20.0f, "sigma %.1f px");
    ImGui::SameLine();
    changed |= ImGui::ColorEdit3("Fog color", fog.color.data(), ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Confidence overlay", &fog.confidenceOverlay);
    ImGui::PopItemWidth();
    drawEffectImage(image, "No fog yet: it needs depth and a camera image.");
    ImGui::End();
    return changed;
}

bool drawAuraPanel(const PanelImage& image, processing::AuraSettings& aura, bool* open) {
    if (!ImGui::Begin(kAuraTitle, open)) {
        ImGui::End();
        return false;
    }
    ImGui::PushItemWidth(ImGui::GetFontSize() * 8.0f);
    int matte = static_cast<int>(aura.matte);
    bool changed = ImGui::Combo("Subject", &matte, "nearest region\0near range\0");
    aura.matte = static_cast<processing::AuraMatte>(matte);
    ImGui::SameLine();
    if (aura.matte == processing::AuraMatte::NearRange) {
        changed |=
            ImGui::DragFloatRange2("Range", &aura.nearMeters, &aura.farMeters, 0.01f, 0.0f, 10.0f, "%.2f m");
    } else {
        changed |= ImGui::SliderFloat("Depth", &aura.regionDepthMeters, 0.05f, 3.0f, "%.2f m");
        ImGui::SameLine();
        changed |= ImGui::SliderFloat("Stands out", &aura.separationMeters, 0.005f, 0.5f, "%.3f m",
                                      ImGuiSliderFlags_Logarithmic);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("How far behind its nearest point a subject must reach before it meets what it "
                              "rests on");
    }
    ImGui::SameLine();
    changed |= ImGui::SliderInt("Ring", &aura.ringPixels, 1, 60, "%d px");
    ImGui::PopItemWidth();
    drawEffectImage(image, "No aura yet: it needs depth and a camera image.");
    ImGui::End();
    return changed;
}

} // namespace dc::ui
