#include "processing/accumulation_worker.h"

#include "base/barrier.h"
#include "base/log.h"

#include <chrono>

namespace dc::processing {

AccumulationWorker::AccumulationWorker() : thread_([this] { run(); }) {}

AccumulationWorker::~AccumulationWorker() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void AccumulationWorker::submit(Request request) {
    {
        std::lock_guard lock(mutex_);
        if (pending_)
            ++skipped_;
        pending_ = std::move(request);
    }
    wake_.notify_one();
}

void AccumulationWorker::clear() {
    {
        std::lock_guard lock(mutex_);
        pending_.reset();
        ++generation_;
    }
    std::lock_guard points(pointsMutex_);
    accumulator_.clear();
    size_ = 0;
}

bool AccumulationWorker::tryRead(const std::function<void(PointAccumulator&)>& read) {
    std::unique_lock points(pointsMutex_, std::try_to_lock);
    if (!points.owns_lock())
        return false;
    read(accumulator_);
    return true;
}

void AccumulationWorker::waitIdle() const {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return !pending_ && !busy_; });
}

void AccumulationWorker::run() {
    for (;;) {
        Request request;
        std::uint64_t generation = 0;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || pending_; });
            if (stopping_)
                return;
            request = std::move(*pending_);
            pending_.reset();
            generation = generation_;
            busy_ = true;
        }
        // A failed frame is left out of the world cloud; the worker goes on with the next.
        if (Status s = base::guarded("accumulation failed", [&] { add(request, generation); }); !s)
            logError(s.error().message);
        {
            std::lock_guard lock(mutex_);
            busy_ = false;
        }
        idle_.notify_all();
    }
}

void AccumulationWorker::add(const Request& request, std::uint64_t generation) {
    std::lock_guard points(pointsMutex_);
    const auto start = std::chrono::steady_clock::now();
    {
        std::lock_guard lock(mutex_);
        if (generation != generation_)
            return; // cleared since this frame was taken: it belongs to what was cleared
    }
    accumulator_.configure(request.budget, request.voxelMeters);
    accumulator_.add({request.depth.get(), request.intrinsics, request.colors.get()}, request.pose,
                     request.minLevel, request.nearMeters);
    size_ = accumulator_.size();
    addMilliseconds_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace dc::processing
