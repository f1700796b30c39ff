#include "base/worker.h"

#include "base/barrier.h"
#include "base/log.h"

#include <utility>

namespace dc::base {

Worker::Worker(std::string what, std::function<void(std::stop_token)> body)
    : outcome_(std::make_shared<Outcome>()) {
    thread_ = std::jthread(
        [what = std::move(what), body = std::move(body), outcome = outcome_](std::stop_token stop) {
            const Status ran = guarded(what, [&] { body(std::move(stop)); });
            if (ran)
                return;
            logError(ran.error().message);
            MutexLock lock(outcome->mutex);
            outcome->error = ran.error().message;
        });
}

Worker::Worker(std::string what, std::function<void()> body)
    : Worker(std::move(what), [body = std::move(body)](std::stop_token) { body(); }) {}

void Worker::join() {
    if (thread_.joinable())
        thread_.join();
}

std::optional<std::string> Worker::error() const {
    if (!outcome_)
        return std::nullopt;
    MutexLock lock(outcome_->mutex);
    return outcome_->error;
}

} // namespace dc::base
