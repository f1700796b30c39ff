#pragma once

#include "devices/synthetic/synthetic_device.h"

#include <chrono>
#include <vector>

namespace dc::tool {

// `count` frames of the synthetic camera as `config` sets it, captured as fast as they are made, before
// anything is timed: a benchmark's source then costs nothing. Empty when the camera cannot start.
inline std::vector<frame::FramePtr> syntheticFrames(devices::SyntheticConfig config, int count) {
    config.paced = false;
    devices::SyntheticDevice device(config);
    std::vector<frame::FramePtr> frames;
    if (!device.open() || !device.start())
        return frames;
    for (int i = 0; i < count; ++i)
        if (auto frame = device.capture(std::chrono::seconds(5)).frame)
            frames.push_back(std::move(frame));
    return frames;
}

} // namespace dc::tool
