#pragma once

#include "base/clock.h"
#include "devices/device.h"
#include "frame/frame.h"

#include <cstdint>
#include <optional>

namespace dc::devices {

// How old a frame is now, in milliseconds, for sources whose timestamps are CLOCK_MONOTONIC capture times
// (V4L2 stamps buffers when the driver receives them): the latency from capture to wherever this is called.
inline double frameAgeMs(const frame::Frame& frame, std::int64_t nowNs = base::monotonicNowNs()) {
    return static_cast<double>(nowNs - frame.timestampNs) / 1e6;
}

// Now on the clock that a source stamps its frames with; nothing when that is no clock of this machine (a
// recording's).
inline std::optional<std::int64_t> nowOnFrameClockNs(const Capabilities& c) {
    if (c.monotonicTimestamps)
        return base::monotonicNowNs();
    if (c.realtimeTimestamps)
        return base::realtimeNowNs();
    return std::nullopt;
}

} // namespace dc::devices
