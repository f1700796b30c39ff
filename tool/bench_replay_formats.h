#pragma once

#include "devices/replay/replay_source.h"

#include <string>

namespace dc::tool {

// Decodes every frame of `source` `passes` times; prints the median pass as frames per second and as a
// multiple of real time (a single pass of a short recording lasts a fraction of a second: too noisy alone).
// Returns the median seconds of one pass.
double decodeAll(const std::string& name, devices::replay::ReplaySource& source, bool color, int passes);

// The same `frames` 1280x720 depth + colour frames as our recording, a ROS 1 bag, an MCAP file and a rosbag2
// .db3, each decoded alike; each format's time per frame is also given against the recording's. Without ROS
// (-DDC_ROS=OFF) only the recording is decoded.
void benchReplayFormats(int frames, int passes);

} // namespace dc::tool
