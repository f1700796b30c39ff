#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace dc::tool {

struct ControlsOptions {
    std::string source;
    std::vector<std::string> sets; // "NAME=VALUE", NAME as v4l2-ctl spells it
    bool json = false;
    std::string load;       // a preset applied before the --set values
    std::string save;       // the values after --load and --set, written as a preset
    bool overwrite = false; // --save may replace an existing file
};

// `depthcloud controls --source S [--load FILE] [--set NAME=VALUE]... [--save FILE] [--json]`: every V4L2
// control of the camera's nodes with its range, default, flags and value; each --set is checked against what
// the control takes (a bad name or value is exit 2 before anything is set), set, and the listing printed as
// read back after.
CLI::App* addControlsCommand(CLI::App& app, ControlsOptions& options);
int runControls(const ControlsOptions& options);

} // namespace dc::tool
