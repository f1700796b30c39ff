#include "processing/accumulation_worker.h"

#include "base/barrier.h"
#include "base/log.h"

#include <chrono>

namespace dc::processing {

AccumulationWorker::AccumulationWorker() : thread_("accumulation", [this] { run(); }) {}

AccumulationWorker::~AccumulationWorker() {
    {
        base::MutexLock lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void AccumulationWorker::submit(Request request, std::size_t source) {
    {
        base::MutexLock lock(mutex_);
        if (!pending_.insert_or_assign(source, std::move(request)).second)
            ++skipped_;
    }
    wake_.notify_one();
}

void AccumulationWorker::clear() {
    {
        base::MutexLock lock(mutex_);
        pending_.clear();
        ++generation_;
    }
    base::MutexLock points(pointsMutex_);
    accumulator_.clear();
    size_ = 0;
}

bool AccumulationWorker::tryRead(const std::function<void(PointAccumulator&)>& read) {
    if (!pointsMutex_.tryLock())
        return false;
    // Through the barrier, so that the mutex is released whatever `read` does.
    const Status s =
        base::guarded("reading the world cloud", [&]() DC_REQUIRES(pointsMutex_) { read(accumulator_); });
    pointsMutex_.unlock();
    if (!s)
        logError(s.error().message);
    return true;
}

void AccumulationWorker::waitIdle() const {
    base::MutexLock lock(mutex_);
    lock.wait(idle_, [this]() DC_REQUIRES(mutex_) { return pending_.empty() && !busy_; });
}

void AccumulationWorker::run() {
    for (;;) {
        Request request;
        std::uint64_t generation = 0;
        {
            base::MutexLock lock(mutex_);
            lock.wait(wake_, [this]() DC_REQUIRES(mutex_) { return stopping_ || !pending_.empty(); });
            if (stopping_)
                return;
            // The next source after the one served last, round the sources waiting.
            auto next = pending_.upper_bound(lastServed_);
            if (next == pending_.end())
                next = pending_.begin();
            lastServed_ = next->first;
            request = std::move(next->second);
            pending_.erase(next);
            generation = generation_;
            busy_ = true;
        }
        // A failed frame is left out of the world cloud; the worker goes on with the next.
        if (Status s = base::guarded("accumulation failed", [&] { add(request, generation); }); !s)
            logError(s.error().message);
        {
            base::MutexLock lock(mutex_);
            busy_ = false;
        }
        idle_.notify_all();
    }
}

void AccumulationWorker::add(const Request& request, std::uint64_t generation) {
    base::MutexLock points(pointsMutex_);
    const auto start = std::chrono::steady_clock::now();
    {
        base::MutexLock lock(mutex_);
        if (generation != generation_)
            return; // cleared since this frame was taken: it belongs to what was cleared
    }
    accumulator_.configure(request.budget, request.voxelMeters);
    accumulator_.add({request.depth.get(), request.intrinsics, request.colours.get()}, request.pose,
                     request.minLevel, request.nearMeters);
    size_ = accumulator_.size();
    addMilliseconds_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace dc::processing
