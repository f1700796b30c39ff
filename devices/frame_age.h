#pragma once

#include "base/clock.h"
#include "frame/frame.h"

#include <cstdint>

namespace dc::devices {

// How old a frame is now, in milliseconds, for sources whose timestamps are CLOCK_MONOTONIC capture times
// (V4L2 stamps buffers when the driver receives them): the latency from capture to wherever this is called.
inline double frameAgeMs(const frame::Frame& frame, std::int64_t nowNs = base::monotonicNowNs()) {
    return static_cast<double>(nowNs - frame.timestampNs) / 1e6;
}

} // namespace dc::devices
