#pragma once

#include "devices/frame.h"
#include "devices/frame_pacer.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <mutex>

namespace dc::devices {

// How old a frame is now, in milliseconds, for sources whose timestamps are CLOCK_MONOTONIC capture times
// (V4L2 stamps buffers when the driver receives them): the latency from capture to wherever this is called.
inline double frameAgeMs(const Frame& frame, std::int64_t nowNs = monotonicNowNs()) {
    return static_cast<double>(nowNs - frame.timestampNs) / 1e6;
}

// The median of the last kSize frame ages. Thread-safe: the consumer adds, anyone reads.
class AgeMeter {
public:
    static constexpr std::size_t kSize = 31;

    void add(double ms) {
        std::lock_guard lock(mutex_);
        samples_[count_++ % kSize] = ms;
    }

    double medianMs() const {
        std::lock_guard lock(mutex_);
        const std::size_t n = std::min(count_, kSize);
        if (n == 0)
            return 0.0;
        std::array<double, kSize> sorted = samples_;
        std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.begin() + n);
        return sorted[n / 2];
    }

private:
    mutable std::mutex mutex_;
    std::array<double, kSize> samples_{};
    std::size_t count_ = 0;
};

} // namespace dc::devices
