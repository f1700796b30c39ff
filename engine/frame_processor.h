#pragma once

#include "base/latest_slot.h"
#include "base/mutex.h"
#include "base/rolling_stats.h"
#include "base/worker.h"
#include "devices/session.h"
#include "engine/demand.h"
#include "engine/processing_graph.h"
#include "engine/stage_stats.h"
#include "processing/accumulation_worker.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

namespace dc::engine {

struct ProcessorCounts {
    std::uint64_t framesProcessed = 0; // new frames made into a result
    std::uint64_t redone = 0;          // results made again for a changed demand, with no new frame
    std::uint64_t framesUnshown =
        0; // new frames whose result was replaced by a newer frame's before it was taken
    std::uint64_t framesSkipped =
        0; // taken from the source but not new: decoded before a seek, or re-delivered
    std::uint64_t resultsTaken = 0;
    std::uint64_t failures = 0; // frames or redos whose processing threw: logged, skipped, and gone on from
};

// One frame's passage through the processor, for the timing view (TimingModel).
struct ProcessorRecord {
    enum class Kind {
        Processed, // a new frame made into a result, from startNs to endNs (CLOCK_MONOTONIC)
        Unshown,   // its result was replaced by a newer frame's before the GL thread took it
        Skipped,   // taken from the session but not new: decoded before a seek, or re-delivered
    };
    Kind kind = Kind::Processed;
    std::uint64_t sequence = 0; // Frame::sequence
    std::int64_t startNs = 0;
    std::int64_t endNs = 0;
};

// The frame processor: its own thread takes the newest frame from the session (latest wins: it never
// queues) and the newest demand from the UI, runs the ProcessingGraph, and hands the ShownFrame to the GL
// thread, latest wins again. A demand that changes makes it run again on the current frame, whatever the
// source is doing (paused, ended, stalled, disconnected). Posed frames also go to accumulation from here.
class FrameProcessor {
public:
    using Clock = std::chrono::steady_clock;

    // `fault` is ProcessingGraph's fault-injection seam, for tests.
    FrameProcessor(StageStats& stages, processing::AccumulationWorker& accumulation,
                   ProcessingGraph::StageFault fault = {});
    ~FrameProcessor();
    FrameProcessor(const FrameProcessor&) = delete;
    FrameProcessor& operator=(const FrameProcessor&) = delete;

    // The source whose frames to process (null: none). A new source starts from nothing: its temporal
    // state, remembered results, the current frame and the counts are dropped.
    void setSession(std::shared_ptr<devices::Session> session);
    // Returns the generation of `demand`: the current one when it equals the demand in force, a new one
    // (and a run on the current frame) when it differs.
    std::uint64_t setDemand(const Demand& demand);
    // After a replay seek: frames decoded before it are dropped, and temporal stages start over.
    void afterSeek(std::uint64_t seekGeneration);

    // The newest result not taken yet.
    std::optional<processing::ShownFramePtr> take();
    // Waits up to `timeout` for a result that satisfies `ready` and takes it (none at the timeout).
    std::optional<processing::ShownFramePtr>
    waitFor(std::chrono::milliseconds timeout,
            const std::function<bool(const processing::ShownFrame&)>& ready);

    ProcessorCounts counts() const;
    // What happened to each frame of the current source since the last call, in order: the frames counts()
    // counts. At most kMaxRecords are kept, the newest, for a processor nobody drains.
    std::vector<ProcessorRecord> drainRecords();
    static constexpr std::size_t kMaxRecords = 4096;
    // Frame arrival to result ready, milliseconds, for new frames (median and percentiles in the stats).
    base::RollingStats latencyMs() const;
    // The processor thread's CPU time per new frame made into a result, milliseconds (the last ones).
    base::RollingStats cpuMs() const;
    std::uint64_t stageRuns(std::string_view stage) const;

private:
    struct Work {
        std::shared_ptr<devices::Session> session;
        std::uint64_t epoch = 0;
        Demand demand;
        std::uint64_t generation = 0;
        std::uint64_t awaitedSeek = 0;
        bool reset = false;
        bool frameSignal = false;
        Clock::time_point arrival;
    };

    void run();
    bool hasWork() const DC_REQUIRES(mutex_);
    std::optional<processing::ShownFramePtr> process(const Work& work);
    // process() inside an exception barrier: a stage that throws costs that result, not the thread.
    std::optional<processing::ShownFramePtr> processGuarded(const Work& work);
    void accumulate(const processing::ShownFrame& shown, const Demand& demand, bool fresh);
    void publish(processing::ShownFramePtr result, const Work& work) DC_REQUIRES(mutex_);
    void addRecord(ProcessorRecord record) DC_REQUIRES(mutex_);
    void onFrame();

    StageStats& stages_;
    processing::AccumulationWorker& accumulation_;
    ProcessingGraph graph_;            // processor thread only
    frame::FramePtr current_;          // processor thread only: the frame results are made of
    std::uint64_t lastGeneration_ = 0; // processor thread only: the demand of the last result
    std::uint64_t skipped_ = 0;        // processor thread only; copied to counts_ under mutex_
    std::uint64_t countedEpoch_ = 0;   // processor thread only: the session skipped_ counts for
    std::uint64_t failed_ = 0;         // processor thread only; copied to counts_ under mutex_
    std::string lastFailure_;          // processor thread only: the last failure logged
    // Processor thread only: records of the work in progress, moved to records_ with its counts.
    std::vector<ProcessorRecord> pending_;
    // Processor thread only: the budget and voxel size accumulation last added with; none while it is off.
    std::optional<std::pair<std::size_t, float>> accumulatedWith_;

    mutable base::Mutex mutex_;
    std::condition_variable wake_; // work for the thread
    std::shared_ptr<devices::Session> session_ DC_GUARDED_BY(mutex_);
    std::uint64_t
        epoch_ DC_GUARDED_BY(mutex_) = 0; // counts sessions, so a result of the old one is never published
    Demand demand_ DC_GUARDED_BY(mutex_);
    std::uint64_t generation_ DC_GUARDED_BY(mutex_) =
        0; // 0: no demand yet, so nothing is processed (nobody asked for anything)
    std::uint64_t doneGeneration_ DC_GUARDED_BY(mutex_) = 0;
    std::uint64_t awaitedSeek_ DC_GUARDED_BY(mutex_) = 0;
    bool reset_ DC_GUARDED_BY(mutex_) = false;
    bool frameReady_ DC_GUARDED_BY(mutex_) = false;
    Clock::time_point arrival_ DC_GUARDED_BY(mutex_);
    bool stopping_ DC_GUARDED_BY(mutex_) = false;
    // Results for the GL thread. Put and reset with mutex_ held, so counts_ and the slot's counts agree;
    // taken without it, so the GL thread never waits for the processor's bookkeeping.
    base::LatestSlot<processing::ShownFramePtr> results_;
    ProcessorCounts counts_ DC_GUARDED_BY(mutex_); // but resultsTaken, which is results_'s count
    std::deque<ProcessorRecord> records_ DC_GUARDED_BY(mutex_);
    base::RollingStats latencyMs_ DC_GUARDED_BY(mutex_);
    base::RollingStats cpuMs_ DC_GUARDED_BY(mutex_);
    std::map<std::string, std::uint64_t, std::less<>>
        runs_ DC_GUARDED_BY(mutex_); // a copy of graph_'s, for other threads
    base::Worker thread_;
};

} // namespace dc::engine
