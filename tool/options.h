#pragma once

#include "frame/frame.h"

#include <optional>
#include <string>

namespace dc::tool {

// Exit codes of every depthcloud command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1; // something went wrong while running
inline constexpr int kExitBadArguments = 2;

struct ViewerOptions {
    std::string source = "synthetic";
    bool headless = false;
    std::optional<int> frames; // stop after this many frames (headless default: 60)
    std::string outDirectory;  // where headless runs (and GUI runs given --out) write their files
    std::optional<frame::Confidence> confidence;
    bool reset = false; // ignore saved settings and layout
};

struct BenchOptions {
    int frames = 120;
    int width = 1280;
    int height = 720;
    double sourceFps = 30.0; // the rate the bench's frames arrive at: a depth camera's, not a flood
    std::string jsonPath;    // also write the results as JSON here
    bool breakdown = false;  // also time the GL points frame without each part of the default view
};

int runHeadless(const ViewerOptions& options);
// Returns kExitFailure with a message when no window can be opened.
int runGui(const ViewerOptions& options);
int runBenchRender(const BenchOptions& options);

} // namespace dc::tool
