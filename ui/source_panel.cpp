#include "ui/panels.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

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

// The folders of recent replays, after the picker's own recent folders: where the user's data lives.
void addRecentReplayFolders(const std::vector<SourceEntry>& recent, FilePickerState& files) {
    for (const SourceEntry& e : recent) {
        if (!e.spec.starts_with("replay:"))
            continue;
        // Options follow the path after colons: ":loop" leaves the parent as it is, and a parent that is no
        // folder (one cut out of ":calib=DIR/FILE") is skipped.
        const std::filesystem::path folder = std::filesystem::path(e.spec.substr(7)).parent_path();
        std::error_code ec;
        const bool known = std::find(files.recentFolders.begin(), files.recentFolders.end(),
                                     folder.string()) != files.recentFolders.end();
        if (!known && files.recentFolders.size() < kMaxRecentFolders &&
            std::filesystem::is_directory(folder, ec))
            files.recentFolders.push_back(folder.string());
    }
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
        ImGui::InputTextWithHint("##spec", "replay:PATH, v4l2:/dev/videoN, usb:VID:PID, ros:TOPIC",
                                 state.spec.data(), state.spec.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("Open") || entered) && state.spec[0] != '\0')
        chosen = std::string(state.spec.data());
    if (ImGui::Button("Browse...")) {
        addRecentReplayFolders(list.recent, state.files);
        state.filesOpen = true;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Pick a recording (.dcrec, .bag, .mcap), a Stray Scanner or a TUM RGB-D folder");
    if (!state.error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", state.error.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
    if (state.filesOpen) {
        if (auto picked = drawFilePicker(state.files, &state.filesOpen))
            chosen = std::move(picked);
    }
    return chosen;
}

} // namespace dc::ui
