#pragma once

#include "base/mutex.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <optional>
#include <utility>

namespace dc::base {

// Single-slot, latest-wins hand-over between threads (librealsense's capacity-1 queue). The producer never
// blocks: a value that nobody has taken yet is replaced and counted, so a slow consumer always gets the
// newest value and the producer (a capture or processing thread) never stalls behind it. Each value is
// taken once.
template <class T> class LatestSlot {
public:
    struct Counts {
        std::uint64_t put = 0;
        std::uint64_t replaced = 0; // put over a value that nobody took: dropped unseen
        std::uint64_t taken = 0;
    };

    // Replaces what is there; true when that was a value nobody took. Ignored (false) once closed.
    bool put(T value) {
        return put(std::move(value), [](const T&, T&) {});
    }
    // As put(value); when `value` replaces one nobody took, `onReplace(unseen, value)` runs first, under the
    // slot's lock, so that what the producer carries over from the unseen value into the new one is decided
    // before any consumer can take either. It must not call the slot.
    template <class OnReplace> bool put(T value, OnReplace onReplace) {
        bool replaced = false;
        {
            MutexLock lock(mutex_);
            if (closed_)
                return false;
            if (slot_) {
                onReplace(*slot_, value);
                replaced = true;
                ++counts_.replaced;
            }
            slot_ = std::move(value);
            ++counts_.put;
        }
        ready_.notify_all();
        return replaced;
    }

    // The newest value not taken yet, if any.
    std::optional<T> take() {
        MutexLock lock(mutex_);
        return takeLocked();
    }

    // Waits up to `timeout` for a value and takes it; none at the timeout or once closed (a value put
    // before close() is still taken).
    std::optional<T> waitTake(std::chrono::milliseconds timeout) {
        return waitTake(timeout, [](const T&) { return true; });
    }
    // Waits up to `timeout` for a value that satisfies `wanted` and takes it. A value that does not is left
    // in the slot (take() still gets it) until a newer one replaces it. `wanted` runs under the slot's lock
    // and must not call the slot.
    template <class Wanted> std::optional<T> waitTake(std::chrono::milliseconds timeout, Wanted wanted) {
        MutexLock lock(mutex_);
        const auto satisfied = [&]() DC_REQUIRES(mutex_) { return slot_ && wanted(*slot_); };
        lock.waitFor(ready_, timeout, [&]() DC_REQUIRES(mutex_) { return closed_ || satisfied(); });
        if (!satisfied())
            return std::nullopt;
        return takeLocked();
    }

    // Wakes every waiter and makes later waits return at once; later values are refused. What the slot
    // holds can still be taken.
    void close() {
        {
            MutexLock lock(mutex_);
            closed_ = true;
        }
        ready_.notify_all();
    }

    // Back to a new slot: empty, open, every count zero (a new source starts from nothing).
    void reset() {
        MutexLock lock(mutex_);
        slot_.reset();
        closed_ = false;
        counts_ = {};
    }

    Counts counts() const {
        MutexLock lock(mutex_);
        return counts_;
    }

private:
    std::optional<T> takeLocked() DC_REQUIRES(mutex_) {
        if (slot_)
            ++counts_.taken;
        return std::exchange(slot_, std::nullopt);
    }

    mutable Mutex mutex_;
    std::condition_variable ready_; // a value was put, or the slot was closed
    std::optional<T> slot_ DC_GUARDED_BY(mutex_);
    bool closed_ DC_GUARDED_BY(mutex_) = false;
    Counts counts_ DC_GUARDED_BY(mutex_);
};

} // namespace dc::base
