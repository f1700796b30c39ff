#pragma once

#include "base/mutex.h"
#include "base/worker.h"
#include "frame/frame.h"
#include "processing/point_accumulator.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>

namespace dc::processing {

// Accumulate mode's work, off the render thread: adding a frame at a large budget costs milliseconds of
// scattered memory access, which would otherwise come out of every viewer frame. Frames are handed over
// latest-wins per source (one still waiting when the same source's next comes is skipped, and counted), and
// the sources waiting are served in turn, so that no source's frames crowd out another's; the render
// thread reads the points between two adds and never waits for one.
class AccumulationWorker {
public:
    // The shown cloud's samples (held, so the producer may move on) and the pose that places them.
    struct Request {
        std::shared_ptr<const frame::DepthData> depth;
        frame::Intrinsics intrinsics;
        std::shared_ptr<const RgbImage> colours;
        frame::Pose pose;
        frame::Confidence minLevel = frame::Confidence::Low;
        float nearMeters = 0.0f;
        std::size_t budget = PointAccumulator::kDefaultBudget;
        float voxelMeters = PointAccumulator::kDefaultVoxelMeters;
    };

    AccumulationWorker();
    ~AccumulationWorker();
    AccumulationWorker(const AccumulationWorker&) = delete;
    AccumulationWorker& operator=(const AccumulationWorker&) = delete;

    // `source` numbers the sources fused in one world cloud (0: the main source).
    void submit(Request request, std::size_t source = 0);
    // Drops the waiting frame and every point; a frame being added right now is discarded too.
    void clear();
    // Calls `read` with the points unless the worker is adding to them right now; returns whether it did.
    bool tryRead(const std::function<void(PointAccumulator&)>& read);
    // Waits until every frame handed over so far has been added (tests, benchmarks).
    void waitIdle() const;

    std::size_t size() const { return size_.load(); }
    std::uint64_t skipped() const { return skipped_.load(); }
    // How long the worker took to add the last frame.
    double lastAddMilliseconds() const { return addMilliseconds_.load(); }

private:
    void run();
    void add(const Request& request, std::uint64_t generation) DC_EXCLUDES(mutex_, pointsMutex_);

    mutable base::Mutex mutex_;
    mutable std::condition_variable wake_, idle_;
    std::map<std::size_t, Request> pending_ DC_GUARDED_BY(mutex_); // by source
    std::size_t lastServed_ DC_GUARDED_BY(mutex_) = 0;
    bool busy_ DC_GUARDED_BY(mutex_) = false;
    bool stopping_ DC_GUARDED_BY(mutex_) = false;
    // Counts clears, so a frame taken before one is not added after it.
    std::uint64_t generation_ DC_GUARDED_BY(mutex_) = 0;

    base::Mutex pointsMutex_;
    PointAccumulator accumulator_ DC_GUARDED_BY(pointsMutex_){10'000};

    std::atomic<std::size_t> size_{0};
    std::atomic<std::uint64_t> skipped_{0};
    std::atomic<double> addMilliseconds_{0.0};
    base::Worker thread_;
};

} // namespace dc::processing
