#pragma once

#include "base/barrier.h"
#include "base/expected.h"
#include "base/log.h"
#include "base/mutex.h"
#include "base/worker.h"

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dc::base {

struct OrderedPoolOptions {
    std::string name;       // the threads', in logs ("recording encoder")
    std::string jobFailure; // a job that throws yields Error "<jobFailure>: <the exception's text>"
    std::size_t workers = 1;
    // Jobs accepted and not yet delivered. Bounds the memory the jobs and their results hold.
    std::size_t capacity = 1;
};

// Jobs run in parallel and their results come out in the order the jobs went in (a recorder encodes frames
// on several threads and writes them in sequence). `workers` threads take jobs in submission order; one more
// thread hands each result to the consumer strictly in that order, one at a time. A job that throws yields
// its Error as its result: no exception crosses a thread, and later jobs go on. Destruction drops the jobs
// no worker has started, delivers the ones running, and joins every thread.
template <class Job, class Result> class OrderedPool {
public:
    // `index` counts the accepted jobs from 0; `worker` is in [0, workers), for state a worker keeps.
    using Work = std::function<Result(Job& job, std::uint64_t index, std::size_t worker)>;
    // Runs on the delivering thread, never two at once; what it throws is logged and ends nothing.
    using Consume = std::function<void(Expected<Result> result)>;

    OrderedPool(OrderedPoolOptions options, Work work, Consume consume)
        : options_(std::move(options)), work_(std::move(work)), consume_(std::move(consume)) {
        options_.workers = std::max<std::size_t>(1, options_.workers);
        options_.capacity = std::max<std::size_t>(1, options_.capacity);
        {
            MutexLock lock(mutex_);
            workersRunning_ = options_.workers;
        }
        for (std::size_t i = 0; i < options_.workers; ++i)
            workers_.emplace_back(options_.name, [this, i] { workLoop(i); });
        deliverer_ = Worker(options_.name + " (in order)", [this] { deliverLoop(); });
    }
    ~OrderedPool() {
        dropQueued();
        finish();
    }
    OrderedPool(const OrderedPool&) = delete;
    OrderedPool& operator=(const OrderedPool&) = delete;

    // Never blocks, because a capture thread that submits must never wait for a disk: false (the job is not
    // taken) while `capacity` jobs are accepted and not delivered, and after finish().
    bool trySubmit(Job job) {
        {
            MutexLock lock(mutex_);
            if (finishing_ || pending_ >= options_.capacity)
                return false;
            queue_.push_back({nextIndex_++, std::move(job)});
            ++pending_;
        }
        queued_.notify_one();
        return true;
    }

    // Jobs accepted and not yet delivered (queued, running, or done and waiting for their turn).
    std::size_t pending() const {
        MutexLock lock(mutex_);
        return pending_;
    }

    // Drops the jobs that no worker has started and returns how many: their results are never delivered,
    // and the results of the others still are, in order.
    std::size_t dropQueued() {
        MutexLock lock(mutex_);
        const std::size_t dropped = queue_.size();
        for (const Queued& q : queue_)
            results_.emplace(q.index, std::nullopt);
        queue_.clear();
        pending_ -= dropped;
        delivered_.notify_one();
        return dropped;
    }

    // Accepts nothing more, runs and delivers every job accepted, and joins the threads. Idempotent; call it
    // from the owner's thread, not from the consumer.
    void finish() {
        {
            MutexLock lock(mutex_);
            finishing_ = true;
        }
        queued_.notify_all();
        for (Worker& w : workers_)
            w.join();
        deliverer_.join();
    }

private:
    struct Queued {
        std::uint64_t index = 0;
        Job job;
    };

    void workLoop(std::size_t worker) {
        MutexLock lock(mutex_);
        for (;;) {
            lock.wait(queued_, [this]() DC_REQUIRES(mutex_) { return finishing_ || !queue_.empty(); });
            if (queue_.empty())
                break;
            Queued next = std::move(queue_.front());
            queue_.pop_front();
            const std::uint64_t index = next.index;
            lock.unlock();
            Expected<Result> result = run(std::move(next), worker);
            lock.lock();
            results_.emplace(index, std::move(result));
            delivered_.notify_one();
        }
        --workersRunning_;
        delivered_.notify_one();
    }

    // Takes the job by value, so that what it holds (a frame) is let go of before the result waits its turn.
    Expected<Result> run(Queued queued, std::size_t worker) {
        std::optional<Result> made;
        const Status ran =
            guarded(options_.jobFailure, [&] { made = work_(queued.job, queued.index, worker); });
        if (!ran)
            return ran.error();
        return std::move(*made);
    }

    void deliverLoop() {
        MutexLock lock(mutex_);
        for (;;) {
            lock.wait(delivered_, [this]() DC_REQUIRES(mutex_) {
                return results_.contains(nextToDeliver_) || workersRunning_ == 0;
            });
            const auto it = results_.find(nextToDeliver_);
            if (it == results_.end())
                return; // the workers have ended, and everything they made is delivered
            std::optional<Expected<Result>> result = std::move(it->second);
            results_.erase(it);
            ++nextToDeliver_;
            if (!result)
                continue; // dropped before it started; pending_ was counted down then
            lock.unlock();
            const Status consumed = guarded(options_.name + ": delivering a result failed",
                                            [&] { consume_(std::move(*result)); });
            if (!consumed)
                logError(consumed.error().message);
            lock.lock();
            --pending_;
        }
    }

    OrderedPoolOptions options_;
    Work work_;
    Consume consume_;
    mutable Mutex mutex_;
    std::condition_variable queued_;    // workers: a job, or finishing
    std::condition_variable delivered_; // the deliverer: a result, or a worker ended
    std::deque<Queued> queue_ DC_GUARDED_BY(mutex_);
    // Results waiting for their turn; none for a job dropped before it started.
    std::map<std::uint64_t, std::optional<Expected<Result>>> results_ DC_GUARDED_BY(mutex_);
    std::uint64_t nextIndex_ DC_GUARDED_BY(mutex_) = 0;
    std::uint64_t nextToDeliver_ DC_GUARDED_BY(mutex_) = 0;
    std::size_t pending_ DC_GUARDED_BY(mutex_) = 0;
    std::size_t workersRunning_ DC_GUARDED_BY(mutex_) = 0;
    bool finishing_ DC_GUARDED_BY(mutex_) = false;
    std::vector<Worker> workers_;
    Worker deliverer_; // last: joined before anything above is destroyed
};

} // namespace dc::base
