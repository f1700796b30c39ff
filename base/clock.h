#pragma once

#include <chrono>
#include <cstdint>

namespace dc::base {

// CLOCK_MONOTONIC now, in nanoseconds: the clock of live frames' timestamps (V4L2 stamps buffers with it),
// and of sources without a clock of their own.
inline std::int64_t monotonicNowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// CLOCK_REALTIME now, in nanoseconds: the clock of ROS header stamps (ROS time without simulation).
inline std::int64_t realtimeNowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

} // namespace dc::base
