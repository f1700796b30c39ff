#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>

namespace dc::base {

// Events per second over the last few events (frames delivered, frames drawn). A ring of arrival times
// rather than a counter reset every second, so the figure is fresh after a handful of events.
class RateMeter {
public:
    using Clock = std::chrono::steady_clock;

    void tick(Clock::time_point now = Clock::now()) {
        const std::uint64_t count = ++count_;
        times_[count % kSize] = now;
        if (count < 2)
            return;
        // The oldest arrival still in the ring is (count - span), span <= kSize - 1.
        const std::uint64_t span = std::min<std::uint64_t>(count - 1, kSize - 1);
        const std::chrono::duration<double> elapsed = now - times_[(count - span) % kSize];
        if (elapsed.count() > 0.0)
            rate_ = static_cast<double>(span) / elapsed.count();
    }

    double perSecond() const { return rate_; }
    std::uint64_t count() const { return count_; }

private:
    static constexpr std::size_t kSize = 32;
    std::array<Clock::time_point, kSize> times_{};
    std::uint64_t count_ = 0;
    double rate_ = 0.0;
};

} // namespace dc::base
