#pragma once

#include "base/expected.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace dc::ui {

inline constexpr const char* kFilePickerTitle = "Open a recording";

// What a path is to the replay: something it opens, a folder to look into, or neither.
enum class PathKind {
    Recording,      // a recording: ours, a ROS bag, MCAP, a rosbag2 folder (devices::replay::classifyCapture)
    StrayDirectory, // a Stray Scanner capture: depth/ beside rgb.mp4
    TumDirectory,   // a TUM RGB-D sequence: rgb.txt and depth.txt
    Folder,         // any other directory
    Other,          // any other file
};

// The replay's own answer (devices::replay::classifyCapture), in the picker's terms; whether the contents
// are sound is the opener's to say.
PathKind classifyPath(const std::filesystem::path& path);
bool isSource(PathKind kind);

// The --source spec that opens `path` (a file or directory dropped on the window, or picked), or why it
// opens nothing, naming the path.
Expected<std::string> sourceSpecForPath(const std::string& path);

struct FilePickerEntry {
    std::string name;
    PathKind kind = PathKind::Other;
};

// Plain state of the picker. `directory` is the folder shown (empty: the most recent folder, else the
// working directory); the listing is read again only when the folder or the filter changes, or on Refresh.
struct FilePickerState {
    std::string directory;
    std::vector<std::string> recentFolders; // newest first, at most kMaxRecentFolders
    bool sourcesOnly = true;                // list only folders and what the replay opens
    std::size_t selected = 0;               // the keyboard's row in `entries`
    std::string message;                    // why the last choice opened nothing
    std::string listedDirectory;            // what `entries` lists
    bool listedSourcesOnly = true;
    std::vector<FilePickerEntry> entries; // folders first, then by name; no hidden files
};

inline constexpr std::size_t kMaxRecentFolders = 8;

// Puts `folder` first in the recent folders (once) and trims the list.
void rememberFolder(FilePickerState& state, const std::string& folder);

// A window listing a folder: a click selects, a double-click or Enter opens (a recording or capture is
// chosen, a folder is entered), Backspace goes to the parent, the arrows move the selection. Returns the
// --source spec of the chosen path, once, and then closes itself (*open = false).
std::optional<std::string> drawFilePicker(FilePickerState& state, bool* open);

} // namespace dc::ui
