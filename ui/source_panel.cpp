#include "ui/panels.h"

namespace dc::ui {

namespace {

// One clickable line per source; returns the spec of the one clicked.
std::optional<std::string> sourceList(const char* heading, const std::vector<SourceEntry>& entries,
                                      const std::string& current) {
    std::optional<std::string> chosen;
    ImGui::TextDisabled("%s", heading);
    if (entries.empty())
        ImGui::TextDisabled("  none");
    for (const SourceEntry& e : entries) {
        if (ImGui::Selectable(e.label.c_str(), e.spec == current))
            chosen = e.spec;
        if (ImGui::IsItemHovered() && e.label != e.spec)
            ImGui::SetTooltip("%s", e.spec.c_str());
    }
    return chosen;
}

} // namespace

std::optional<std::string> drawSourcePanel(const SourceList& list, SourcePanelState& state, bool* open) {
    if (!ImGui::Begin(kSourceTitle, open)) {
        ImGui::End();
        return std::nullopt;
    }
    std::optional<std::string> chosen;
    for (const auto& [heading, entries] :
         {std::pair{"Cameras", &list.live}, std::pair{"Recent", &list.recent},
          std::pair{"Built in", &list.builtIn}}) {
        if (auto c = sourceList(heading, *entries, list.current))
            chosen = c;
        ImGui::Spacing();
    }
    ImGui::Separator();
    ImGui::SetNextItemWidth(-ImGui::GetFontSize() * 4.0f);
    const bool entered =
        ImGui::InputTextWithHint("##spec", "replay:PATH, v4l2:/dev/videoN, usb:VID:PID", state.spec.data(),
                                 state.spec.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("Open") || entered) && state.spec[0] != '\0')
        chosen = std::string(state.spec.data());
    if (!state.error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", state.error.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
    return chosen;
}

} // namespace dc::ui
