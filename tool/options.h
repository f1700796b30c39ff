#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "frame/frame.h"
#include "ui/settings.h"
#include "ui/source_settings.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::tool {

// Exit codes of every depthcloud command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1; // something went wrong while running
inline constexpr int kExitBadArguments = 2;

// A command's one-line error on stderr, "depthcloud COMMAND: error: MESSAGE" ("depthcloud: error: ..." for
// the viewer itself), and the exit code to return with it.
inline int commandFailed(const char* command, const std::string& message, int code = kExitFailure) {
    std::fprintf(stderr, "depthcloud%s%s: error: %s\n", *command ? " " : "", command, message.c_str());
    return code;
}

struct ViewerOptions {
    std::string source = "synthetic";
    std::vector<std::string> companions; // --source given again: sources fused with the first in one cloud
    bool headless = false;
    std::optional<int> frames; // stop after this many frames (headless default: 60)
    std::string outDirectory;  // where headless runs (and GUI runs given --out) write their files
    std::optional<frame::Confidence> confidence;
    bool reset = false;            // ignore saved settings and layout
    std::string settingsPath;      // --settings: read instead of the saved settings
    std::vector<std::string> sets; // --set SECTION.KEY=VALUE, applied in order after them
};

struct BenchOptions {
    int frames = 120;
    int width = 1280;
    int height = 720;
    double sourceFps = 30.0; // the rate the bench's frames arrive at: a depth camera's, not a flood
    std::string jsonPath;    // also write the results as JSON here
    bool breakdown = false;  // also time the GL points frame without each part of the default view
};

// The settings a run starts from: `saved` (the user's, or the defaults for a headless run), or the
// --settings file instead, then each --set in order and --confidence. An Error names the argument.
Expected<ui::Settings> chosenSettings(ui::Settings saved, const ViewerOptions& options);
// Each further source's settings (one per options.companions): the main source's, or its own where a
// --set sourceN.NAME=VALUE names it (N from 2: the first --source is source 1). An Error names the
// argument.
Expected<std::vector<ui::SourceSettings>> furtherSourcesSettings(const ui::Settings& main,
                                                                 const ViewerOptions& options);

// Both run `device`, which runViewer opened from options.source once: a second open would repeat its
// warnings and open a live camera twice.
// `companions` are the devices of options.companions, opened there too.
using Devices = std::vector<std::unique_ptr<devices::Device>>;
int runHeadless(const ViewerOptions& options, std::unique_ptr<devices::Device> device, Devices companions);
// Returns kExitFailure with a message when no window can be opened.
int runGui(const ViewerOptions& options, std::unique_ptr<devices::Device> device, Devices companions);
int runBenchRender(const BenchOptions& options);

} // namespace dc::tool
