#pragma once

#include "base/mutex.h"

#include <functional>
#include <memory>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>

namespace dc::base {

// One thread of the project, whatever it does. Its body runs inside the exception barrier (guarded): an
// exception that escapes it ends this thread, never the process; its message ("<what>: <exception>") is
// logged as an error and kept for the owner to show (error()). Destroying a Worker, or assigning another
// to it, asks the body to stop (its std::stop_token) and joins it, so a Worker declared after the state
// its body uses never outlives that state.
class Worker {
public:
    Worker() = default;
    Worker(std::string what, std::function<void(std::stop_token)> body);
    // For a body that its owner stops by its own means (a flag and a condition variable, an eventfd).
    Worker(std::string what, std::function<void()> body);
    Worker(Worker&&) noexcept = default;
    Worker& operator=(Worker&&) noexcept = default;
    ~Worker() = default;

    // Asks the body to stop through its token; returns at once.
    void requestStop() { thread_.request_stop(); }
    // Waits for the body to return (at once if it has, or if there is no thread).
    void join();
    bool joinable() const { return thread_.joinable(); }
    // The message of the exception that ended the body; none while it runs or after it returned.
    std::optional<std::string> error() const;

private:
    struct Outcome {
        mutable Mutex mutex;
        std::optional<std::string> error DC_GUARDED_BY(mutex);
    };
    std::shared_ptr<Outcome> outcome_; // shared with the thread, which may record into it as it ends
    std::jthread thread_;              // last: joined before anything above is destroyed
};

} // namespace dc::base
