#pragma once

#include <chrono>
#include <cstdint>
#include <ctime>

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

// CPU time in milliseconds used by the calling thread (CLOCK_THREAD_CPUTIME_ID), or by every thread of the
// process (CLOCK_PROCESS_CPUTIME_ID): what work costs whatever else the machine runs, without the time spent
// waiting for a core or sleeping.
inline double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

inline double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

} // namespace dc::base
