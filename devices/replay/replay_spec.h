#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "devices/replay/replay_source.h"

#include <memory>
#include <string>

namespace dc::devices::replay {

inline constexpr const char* kReplaySpecHelp =
    "replay:PATH[:loop][:paused][:speed=X][:calib=FILE][:topics=DEPTH[,COLOR]]";

// The part of a --source value after "replay:": PATH, then options from the right (a path may itself
// contain ':'). PATH is a recording, a ROS bag, a ROS 2 recording (MCAP), a Stray Scanner directory or a TUM
// RGB-D directory.
Expected<std::unique_ptr<Device>> openReplaySpec(const std::string& rest);

// The source behind a replay spec, for consumers that need random access rather than a paced device
// (export, benchmarks): "replay:PATH[:options]" or a bare PATH. Playback options and pose= are ignored.
Expected<std::unique_ptr<ReplaySource>> openReplaySpecSource(const std::string& spec);

} // namespace dc::devices::replay
