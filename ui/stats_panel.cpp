#include "ui/panels.h"

#include <algorithm>

namespace dc::ui {

namespace {

void stageRow(const StageHistory& stage) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(stage.name.c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%.2f", stage.medianMs);
    ImGui::TableNextColumn();
    ImGui::Text("%.2f", stage.maxMs);
    ImGui::TableNextColumn();
    const float top = std::max(1.0f, static_cast<float>(stage.maxMs) * 1.1f);
    ImGui::PushID(stage.name.c_str());
    ImGui::PlotLines("##history", stage.history.data(), static_cast<int>(stage.history.size()), 0, nullptr,
                     0.0f, top, ImVec2(-1.0f, ImGui::GetTextLineHeight() * 1.6f));
    ImGui::PopID();
}

} // namespace

void drawStatsPanel(const StatsView& s, bool* open) {
    if (!ImGui::Begin(kStatsTitle, open)) {
        ImGui::End();
        return;
    }
    const engine::FrameCounts& f = s.frames;
    ImGui::Text("device %.1f fps, shown %.1f fps, UI %.1f fps", f.deliveredPerSecond, f.shownPerSecond,
                s.uiFps);
    ImGui::Text("frames: %llu delivered = %llu shown + %llu dropped (+ in flight)",
                static_cast<unsigned long long>(f.delivered), static_cast<unsigned long long>(f.shown),
                static_cast<unsigned long long>(f.dropped));
    ImGui::Text("points %llu", static_cast<unsigned long long>(s.pointsDrawn));
    if (s.latencyMs)
        ImGui::Text("device to screen %.1f ms (median)", *s.latencyMs);
    else
        ImGui::TextDisabled("device to screen: n/a (the source's clock is not this machine's)");
    ImGui::Text("memory %.0f MiB resident", s.residentMebibytes);
    constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV;
    if (ImGui::BeginTable("##stages", 4, kFlags)) {
        ImGui::TableSetupColumn("stage");
        ImGui::TableSetupColumn("median ms");
        ImGui::TableSetupColumn("max ms");
        ImGui::TableSetupColumn("last seconds", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableHeadersRow();
        for (const StageHistory& stage : s.stages)
            stageRow(stage);
        ImGui::EndTable();
    }
    ImGui::End();
}

} // namespace dc::ui
