#include "ui/file_picker.h"

#include "devices/replay/replay_source.h"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <system_error>

namespace dc::ui {

namespace fs = std::filesystem;

namespace {

bool pathExists(const fs::path& p) {
    std::error_code ec;
    return fs::exists(p, ec);
}

bool listedAsFolder(PathKind kind) {
    return kind != PathKind::Recording && kind != PathKind::Other;
}

const char* kindLabel(PathKind kind) {
    switch (kind) {
    case PathKind::StrayDirectory:
        return "Stray Scanner capture";
    case PathKind::TumDirectory:
        return "TUM RGB-D sequence";
    case PathKind::Recording:
        return "recording";
    case PathKind::Folder:
    case PathKind::Other:
        break;
    }
    return "";
}

// The folder's entries, folders first, then by name; hidden ones (a leading dot) left out.
std::vector<FilePickerEntry> listFolder(const fs::path& folder, bool sourcesOnly, std::string& problem) {
    std::vector<FilePickerEntry> entries;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.')
            continue;
        const PathKind kind = classifyPath(it->path());
        if (sourcesOnly && kind == PathKind::Other)
            continue;
        entries.push_back({name, kind});
    }
    if (ec)
        problem = "cannot list " + folder.string() + ": " + ec.message();
    std::sort(entries.begin(), entries.end(), [](const FilePickerEntry& a, const FilePickerEntry& b) {
        if (listedAsFolder(a.kind) != listedAsFolder(b.kind))
            return listedAsFolder(a.kind);
        return a.name < b.name;
    });
    return entries;
}

void goTo(FilePickerState& state, const fs::path& folder) {
    state.directory = folder.string();
    state.selected = 0;
    state.message.clear();
}

void goToParent(FilePickerState& state) {
    fs::path p = fs::path(state.directory).lexically_normal();
    if (!p.has_filename() && p.has_parent_path()) // "a/b/" names the folder b
        p = p.parent_path();
    if (p.has_parent_path() && p.parent_path() != p)
        goTo(state, p.parent_path());
}

void refreshListing(FilePickerState& state) {
    if (state.directory.empty()) {
        std::error_code ec;
        state.directory =
            state.recentFolders.empty() ? fs::current_path(ec).string() : state.recentFolders[0];
    }
    if (state.directory == state.listedDirectory && state.sourcesOnly == state.listedSourcesOnly)
        return;
    std::string problem;
    state.entries = listFolder(state.directory, state.sourcesOnly, problem);
    state.listedDirectory = state.directory;
    state.listedSourcesOnly = state.sourcesOnly;
    state.selected = std::min(state.selected, state.entries.empty() ? 0 : state.entries.size() - 1);
    if (!problem.empty())
        state.message = problem;
}

// Opens entry `index`: a folder is entered, a source chosen; anything else says why it is not one.
std::optional<std::string> activate(FilePickerState& state, std::size_t index) {
    if (index >= state.entries.size())
        return std::nullopt;
    const FilePickerEntry entry = state.entries[index];
    const fs::path path = fs::path(state.directory) / entry.name;
    if (entry.kind == PathKind::Folder) {
        goTo(state, path);
        return std::nullopt;
    }
    Expected<std::string> spec = sourceSpecForPath(path.string());
    if (!spec) {
        state.message = spec.error().message;
        return std::nullopt;
    }
    rememberFolder(state, state.directory);
    state.message.clear();
    return *spec;
}

// Arrows move the selection, Enter opens it, Backspace goes up: only while the picker has the keyboard and
// no text field does. Returns whether the selection moved, so the list scrolls to it.
bool handleKeys(FilePickerState& state, std::optional<std::size_t>& activated) {
    if (!ImGui::IsWindowFocused(ImGuiFocusedFlags_RootAndChildWindows) || ImGui::GetIO().WantTextInput)
        return false;
    const auto pressed = [](ImGuiKey key, bool repeat) {
        return ImGui::IsKeyPressed(ImGui::GetKeyIndex(key), repeat);
    };
    const std::size_t count = state.entries.size();
    bool moved = false;
    if (pressed(ImGuiKey_DownArrow, true) && state.selected + 1 < count) {
        ++state.selected;
        moved = true;
    }
    if (pressed(ImGuiKey_UpArrow, true) && state.selected > 0) {
        --state.selected;
        moved = true;
    }
    if (pressed(ImGuiKey_Enter, false) || pressed(ImGuiKey_KeyPadEnter, false))
        activated = state.selected;
    if (pressed(ImGuiKey_Backspace, false))
        goToParent(state);
    return moved;
}

void drawLocationRow(FilePickerState& state) {
    if (ImGui::Button("Up"))
        goToParent(state);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The parent folder [Backspace]");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 10.0f);
    if (ImGui::BeginCombo("##recent", "Recent folders")) {
        for (std::size_t i = 0; i < state.recentFolders.size(); ++i) {
            ImGui::PushID(static_cast<int>(i));
            if (ImGui::Selectable(state.recentFolders[i].c_str()))
                goTo(state, state.recentFolders[i]);
            ImGui::PopID();
        }
        if (state.recentFolders.empty())
            ImGui::TextDisabled("none yet");
        ImGui::EndCombo();
    }
    ImGui::SameLine();
    ImGui::Checkbox("Sources only", &state.sourcesOnly);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "List only folders, recordings (.dcrec, .bag, .mcap), Stray Scanner and TUM RGB-D captures");
    ImGui::SameLine();
    if (ImGui::Button("Refresh"))
        state.listedDirectory.clear();
    ImGui::TextWrapped("%s", state.directory.c_str());
}

// The listing, above one row of buttons; returns the entry double-clicked, if any.
std::optional<std::size_t> drawEntries(FilePickerState& state, bool scrollToSelected) {
    std::optional<std::size_t> activated;
    if (!ImGui::BeginChild("entries", ImVec2(0.0f, -ImGui::GetFrameHeightWithSpacing()), true)) {
        ImGui::EndChild();
        return activated;
    }
    if (state.entries.empty())
        ImGui::TextDisabled(state.sourcesOnly ? "no folders or recordings here" : "empty folder");
    for (std::size_t i = 0; i < state.entries.size(); ++i) {
        const FilePickerEntry& e = state.entries[i];
        ImGui::PushID(static_cast<int>(i));
        const std::string label = listedAsFolder(e.kind) ? e.name + "/" : e.name;
        if (e.kind == PathKind::Other)
            ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
        if (ImGui::Selectable(label.c_str(), state.selected == i, ImGuiSelectableFlags_AllowDoubleClick)) {
            state.selected = i;
            if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
                activated = i;
        }
        if (e.kind == PathKind::Other)
            ImGui::PopStyleColor();
        if (scrollToSelected && state.selected == i)
            ImGui::SetScrollHereY();
        if (const char* kind = kindLabel(e.kind); *kind) {
            ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize(kind).x);
            ImGui::TextDisabled("%s", kind);
        }
        ImGui::PopID();
    }
    ImGui::EndChild();
    return activated;
}

} // namespace

PathKind classifyPath(const fs::path& path) {
    switch (devices::replay::classifyCapture(path)) {
    case devices::replay::CaptureKind::DcRecording:
    case devices::replay::CaptureKind::RosBag:
    case devices::replay::CaptureKind::Mcap:
    case devices::replay::CaptureKind::Rosbag2:
        return PathKind::Recording;
    case devices::replay::CaptureKind::StrayCapture:
        return PathKind::StrayDirectory;
    case devices::replay::CaptureKind::TumSequence:
        return PathKind::TumDirectory;
    case devices::replay::CaptureKind::Folder:
        return PathKind::Folder;
    case devices::replay::CaptureKind::OtherFile:
    case devices::replay::CaptureKind::Missing:
        break;
    }
    return PathKind::Other;
}

bool isSource(PathKind kind) {
    return kind == PathKind::Recording || kind == PathKind::StrayDirectory || kind == PathKind::TumDirectory;
}

Expected<std::string> sourceSpecForPath(const std::string& path) {
    if (path.empty())
        return Error{"no path to open"};
    if (!pathExists(path))
        return Error{path + " does not exist"};
    const PathKind kind = classifyPath(path);
    if (isSource(kind))
        return "replay:" + path;
    if (kind == PathKind::Folder)
        return Error{path + ": a folder, but neither a Stray Scanner capture (depth/, rgb.mp4, "
                            "camera_matrix.csv, odometry.csv) nor a TUM RGB-D sequence (rgb.txt, depth.txt)"};
    return Error{
        path + ": not a recording (.dcrec, .bag, .mcap), a Stray Scanner directory or a TUM RGB-D directory"};
}

void rememberFolder(FilePickerState& state, const std::string& folder) {
    auto& recent = state.recentFolders;
    recent.erase(std::remove(recent.begin(), recent.end(), folder), recent.end());
    recent.insert(recent.begin(), folder);
    if (recent.size() > kMaxRecentFolders)
        recent.resize(kMaxRecentFolders);
}

std::optional<std::string> drawFilePicker(FilePickerState& state, bool* open) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(viewport->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(ImGui::GetFontSize() * 36.0f, ImGui::GetFontSize() * 26.0f),
                             ImGuiCond_FirstUseEver);
    if (!ImGui::Begin(kFilePickerTitle, open)) {
        ImGui::End();
        return std::nullopt;
    }
    refreshListing(state);
    std::optional<std::size_t> activated;
    const bool moved = handleKeys(state, activated);
    refreshListing(state); // Backspace may have changed the folder
    drawLocationRow(state);
    if (!state.message.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", state.message.c_str());
        ImGui::PopTextWrapPos();
    }
    if (const auto clicked = drawEntries(state, moved))
        activated = clicked;
    if (ImGui::Button("Open"))
        activated = state.selected;
    ImGui::SameLine();
    bool close = ImGui::Button("Cancel");
    std::optional<std::string> chosen;
    if (activated)
        chosen = activate(state, *activated);
    close |= chosen.has_value();
    if (close && open)
        *open = false;
    ImGui::End();
    return chosen;
}

} // namespace dc::ui
