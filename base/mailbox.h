#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace dc::base {

// Single-slot, latest-wins hand-over between one producer and one consumer (librealsense's capacity-1
// queue). The producer never blocks: a value that the consumer has not taken yet is replaced and counted
// as dropped, so a slow viewer always sees the newest frame and the capture thread never stalls.
template <class T> class Mailbox {
public:
    void post(T value) {
        std::lock_guard lock(mutex_);
        if (slot_)
            ++dropped_;
        slot_ = std::move(value);
        ++posted_;
        ready_.notify_one();
    }

    std::optional<T> take() {
        std::lock_guard lock(mutex_);
        return std::exchange(slot_, std::nullopt);
    }

    // Blocks up to `timeout` for a value (headless runs and tests consume every frame they can get).
    std::optional<T> waitTake(std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        ready_.wait_for(lock, timeout, [this] { return slot_.has_value(); });
        return std::exchange(slot_, std::nullopt);
    }

    std::uint64_t dropped() const {
        std::lock_guard lock(mutex_);
        return dropped_;
    }

    std::uint64_t posted() const {
        std::lock_guard lock(mutex_);
        return posted_;
    }

private:
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::optional<T> slot_;
    std::uint64_t dropped_ = 0;
    std::uint64_t posted_ = 0;
};

} // namespace dc::base
