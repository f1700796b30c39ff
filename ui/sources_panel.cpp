#include "ui/panels.h"

#include <imgui.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace dc::ui {

namespace {

constexpr float kThumbnailWidth = 128.0f;

// A rotation of `degrees` about the world's x, y and z axes in turn (small nudges: the order hardly
// matters at the size of one frame's drag).
frame::RigidTransform nudge(const std::array<float, 3>& moveMm, const std::array<float, 3>& turnDegrees) {
    const auto rad = [](float d) { return static_cast<double>(d) * 3.14159265358979323846 / 180.0; };
    const double cx = std::cos(rad(turnDegrees[0])), sx = std::sin(rad(turnDegrees[0]));
    const double cy = std::cos(rad(turnDegrees[1])), sy = std::sin(rad(turnDegrees[1]));
    const double cz = std::cos(rad(turnDegrees[2])), sz = std::sin(rad(turnDegrees[2]));
    frame::RigidTransform t;
    // Rz * Ry * Rx, row-major.
    t.rotation = {cz * cy,
                  cz * sy * sx - sz * cx,
                  cz * sy * cx + sz * sx,
                  sz * cy,
                  sz * sy * sx + cz * cx,
                  sz * sy * cx - cz * sx,
                  -sy,
                  cy * sx,
                  cy * cx};
    t.translationMeters = {moveMm[0] * 1e-3, moveMm[1] * 1e-3, moveMm[2] * 1e-3};
    return t;
}

// Draws it (when it has a picture) and returns whether it did.
bool drawThumbnail(const PanelImage& image) {
    if (image.empty())
        return false;
    const float height = kThumbnailWidth * static_cast<float>(image.height) / static_cast<float>(image.width);
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)),
                 {kThumbnailWidth, height}, image.bottomUp ? ImVec2{0, 1} : ImVec2{0, 0},
                 image.bottomUp ? ImVec2{1, 0} : ImVec2{1, 1});
    return true;
}

// Each row's widgets carry its number after "##", so that a test can find them by label.
std::string labelOf(const char* text, std::size_t row) {
    return std::string(text) + "##" + std::to_string(row + 1);
}

void drawFrames(const SourceRow& row) {
    const engine::FrameCounts& f = row.frames;
    ImGui::TextWrapped("%s, %.1f of %.1f fps shown", row.state.c_str(), f.shownPerSecond,
                       f.deliveredPerSecond);
    ImGui::TextWrapped("%llu shown + %llu dropped of %llu delivered",
                       static_cast<unsigned long long>(f.shown), static_cast<unsigned long long>(f.dropped),
                       static_cast<unsigned long long>(f.delivered));
}

// "Own processing": off, the source is processed and filtered as the main source is; on, with its own
// depth shown, smoothing, upsampling and cloud confidence, starting from the main source's.
void drawOwnProcessing(SourceSettings& own, std::size_t number) {
    bool separate = !own.followsMain;
    if (ImGui::Checkbox(labelOf("Own processing", number).c_str(), &separate))
        own.followsMain = !separate;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Off: this source is processed as the main source is (the Controls panel).\n"
                          "On: its own processing and cloud confidence, set here.");
    if (!separate)
        return;
    ImGui::PushID(static_cast<int>(number));
    ImGui::Indent();
    int level = static_cast<int>(own.minConfidence);
    ImGui::PushItemWidth(ImGui::GetFontSize() * 10.0f);
    ImGui::Combo("Cloud confidence", &level, "all\0medium and high\0high only\0");
    ImGui::PopItemWidth();
    own.minConfidence = static_cast<frame::Confidence>(level);
    ControlsContext context;
    context.smoothingAvailable = true;
    context.upsamplingAvailable = true;
    processingControls(own.processing, context);
    ImGui::Unindent();
    ImGui::PopID();
}

// The companion's look, placement and figures; sets `actions` for its buttons. `gizmo` is the companion
// whose gizmo the Cloud panel draws: its toggle moves it here, or hides it.
void drawCompanion(const SourceRow& row, std::size_t index, SourcesActions& actions,
                   std::optional<std::size_t>& gizmo) {
    CompanionLook& look = *row.look;
    const std::size_t number = index + 1; // the row's: the main source is row 0
    ImGui::Checkbox(labelOf("Visible", number).c_str(), &look.visible);
    ImGui::SameLine();
    ImGui::Checkbox(labelOf("Tint", number).c_str(), &look.tinted);
    ImGui::SameLine();
    ImGui::ColorEdit3(labelOf("", number).c_str(), look.tint.data(), ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    bool gizmoShown = gizmo == index;
    if (ImGui::Checkbox(labelOf("Gizmo", number).c_str(), &gizmoShown))
        gizmo = gizmoShown ? std::optional(index) : std::nullopt;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Arrows and rings at this source's camera in the Point cloud panel: drag an arrow\n"
                          "to move it along that world axis, a ring to turn it about that axis.");
    if (row.overlap)
        ImGui::TextWrapped("overlap: %.1f mm median over %.0f %% of the main source", row.overlap->medianMm,
                           100.0 * row.overlap->overlapFraction);
    else
        ImGui::TextDisabled("overlap: no shared surface yet");
    if (row.skewMs)
        ImGui::TextWrapped("skew: %+.1f ms from the main source's frame (median %+.1f ms)", *row.skewMs,
                           row.skewMedianMs.value_or(*row.skewMs));
    if (!row.paired)
        ImGui::TextColored({1.0f, 0.6f, 0.2f, 1.0f}, "not drawn: beyond the pairing tolerance");
    // Dragged, each field moves the source by what it was dragged this frame (in the world frame).
    std::array<float, 3> moveMm{};
    std::array<float, 3> turnDegrees{};
    ImGui::PushItemWidth(ImGui::GetFontSize() * 12.0f);
    const bool moved =
        ImGui::DragFloat3(labelOf("Move (mm)", number).c_str(), moveMm.data(), 0.5f, -50.0f, 50.0f, "drag");
    const bool turned = ImGui::DragFloat3(labelOf("Turn (deg)", number).c_str(), turnDegrees.data(), 0.05f,
                                          -5.0f, 5.0f, "drag");
    ImGui::PopItemWidth();
    if (moved || turned)
        look.correction = frame::compose(nudge(moveMm, turnDegrees), look.correction);
    if (ImGui::Button(labelOf("Refine (ICP)", number).c_str()))
        actions.refine = index;
    ImGui::SameLine();
    if (ImGui::Button(labelOf("Reset placement", number).c_str()))
        actions.resetPlacement = index;
    ImGui::SameLine();
    if (ImGui::Button(labelOf("Remove", number).c_str()))
        actions.remove = index;
    if (row.own)
        drawOwnProcessing(*row.own, number);
}

} // namespace

SourcesActions drawSourcesPanel(const std::vector<SourceRow>& rows, SourcesPanelState& state,
                                float& pairingToleranceMs, bool* open) {
    SourcesActions actions;
    if (!ImGui::Begin(kSourcesTitle, open)) {
        ImGui::End();
        return actions;
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const SourceRow& row = rows[i];
        const std::string header = (i == 0 ? "Main: " : "Source " + std::to_string(i + 1) + ": ") + row.name +
                                   "##" + std::to_string(i + 1);
        if (ImGui::CollapsingHeader(header.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::BeginGroup();
            const bool thumbnails = drawThumbnail(row.depth) | drawThumbnail(row.camera);
            ImGui::EndGroup();
            if (thumbnails)
                ImGui::SameLine();
            ImGui::BeginGroup();
            drawFrames(row);
            if (row.look)
                drawCompanion(row, i - 1, actions, state.gizmo);
            ImGui::EndGroup();
        }
    }
    ImGui::Separator();
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 7.0f);
    const bool entered =
        ImGui::InputTextWithHint("##spec", "another --source, e.g. synthetic:pose=0.2,0,0,0,0,0,1",
                                 state.spec.data(), state.spec.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if ((ImGui::Button("Add source") || entered) && state.spec[0] != '\0')
        actions.add = std::string(state.spec.data());
    ImGui::PushItemWidth(ImGui::GetFontSize() * 10.0f);
    ImGui::SliderFloat("Pairing tolerance", &pairingToleranceMs, 0.0f, 100.0f,
                       pairingToleranceMs > 0.0f ? "%.0f ms" : "off");
    ImGui::PopItemWidth();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A further source is drawn only while its frame is this close in time to the main "
                          "source's; off: each source's newest frame");
    if (rows.size() > 1 && ImGui::Button("Save placements"))
        actions.savePlacements = true;
    if (!state.message.empty())
        ImGui::TextWrapped("%s", state.message.c_str());
    ImGui::End();
    return actions;
}

} // namespace dc::ui
