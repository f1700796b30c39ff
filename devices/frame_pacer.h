#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <thread>

namespace dc::devices {

// Releases frames at a steady rate for sources that are not paced by hardware (synthetic, lists, replay).
// A consumer that fell behind by more than a frame resumes the cadence instead of getting a burst.
class FramePacer {
public:
    using Clock = std::chrono::steady_clock;

    explicit FramePacer(double fps = 30.0) { setRate(fps); }

    void setRate(double fps) {
        period_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps));
    }
    void restart() { next_ = Clock::now(); }

    // Sleeps until the next frame is due and returns true, or sleeps `timeout` and returns false when the
    // frame is due later than that (so the capture loop can notice a stop request).
    bool waitForNext(std::chrono::milliseconds timeout) {
        if (next_ - Clock::now() > timeout) {
            std::this_thread::sleep_for(timeout);
            return false;
        }
        std::this_thread::sleep_until(next_);
        next_ = std::max(next_ + period_, Clock::now());
        return true;
    }

private:
    Clock::duration period_{};
    Clock::time_point next_{};
};

} // namespace dc::devices
