#include "engine/frame_processor.h"

#include "base/barrier.h"
#include "base/clock.h"
#include "base/log.h"

#include <utility>

namespace dc::engine {

namespace {

bool decodedBeforeSeek(const frame::Frame& frame, std::uint64_t awaitedSeek) {
    return frame.replay && frame.replay->seekGeneration < awaitedSeek;
}

} // namespace

FrameProcessor::FrameProcessor(StageStats& stages, processing::AccumulationWorker& accumulation,
                               ProcessingGraph::StageFault fault)
    : stages_(stages), accumulation_(accumulation) {
    graph_.setStageFault(std::move(fault));
    thread_ = base::Worker("frame processor", [this] { run(); });
}

FrameProcessor::~FrameProcessor() {
    setSession(nullptr);
    {
        base::MutexLock lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void FrameProcessor::setSession(std::shared_ptr<devices::Session> session) {
    std::shared_ptr<devices::Session> old;
    {
        base::MutexLock lock(mutex_);
        old = std::exchange(session_, session);
        ++epoch_;
        reset_ = true;
        frameReady_ = session != nullptr; // frames may be waiting already
        awaitedSeek_ = 0;
        results_.reset();
        // The counts are the source's: another source's frames were neither shown nor dropped by this one.
        counts_ = {};
        records_.clear();
    }
    // Once setFrameListener returns, the old session's capture thread no longer calls into us.
    if (old)
        old->setFrameListener({});
    if (session)
        session->setFrameListener([this] { onFrame(); });
    wake_.notify_all();
}

void FrameProcessor::onFrame() {
    {
        base::MutexLock lock(mutex_);
        frameReady_ = true;
        arrival_ = Clock::now();
    }
    wake_.notify_all();
}

std::uint64_t FrameProcessor::setDemand(const Demand& demand) {
    base::MutexLock lock(mutex_);
    if (demand == demand_ && generation_ > 0)
        return generation_;
    demand_ = demand;
    ++generation_;
    wake_.notify_all();
    return generation_;
}

void FrameProcessor::afterSeek(std::uint64_t seekGeneration) {
    {
        base::MutexLock lock(mutex_);
        awaitedSeek_ = std::max(awaitedSeek_, seekGeneration);
        reset_ = true;
    }
    wake_.notify_all();
}

bool FrameProcessor::hasWork() const {
    return stopping_ || (generation_ > 0 && (frameReady_ || reset_ || generation_ != doneGeneration_));
}

void FrameProcessor::run() {
    base::MutexLock lock(mutex_);
    for (;;) {
        lock.wait(wake_, [this]() DC_REQUIRES(mutex_) { return hasWork(); });
        if (stopping_)
            return;
        const Work work{session_,
                        epoch_,
                        demand_,
                        generation_,
                        awaitedSeek_,
                        std::exchange(reset_, false),
                        std::exchange(frameReady_, false),
                        arrival_};
        lock.unlock();
        const double cpuStart = base::threadCpuMs();
        const std::int64_t startNs = base::monotonicNowNs();
        std::optional<processing::ShownFramePtr> result = processGuarded(work);
        const double cpuMs = base::threadCpuMs() - cpuStart;
        if (result && (*result)->newFrame)
            pending_.push_back({ProcessorRecord::Kind::Processed, (*result)->frame->sequence, startNs,
                                base::monotonicNowNs()});
        lock.lock();
        if (result && (*result)->newFrame)
            cpuMs_.add(cpuMs);
        doneGeneration_ = work.generation;
        runs_ = graph_.allRuns();
        if (work.epoch == epoch_) {
            counts_.framesSkipped = skipped_;
            counts_.failures = failed_;
            for (const ProcessorRecord& r : pending_)
                addRecord(r);
            if (result)
                publish(std::move(*result), work);
        }
        pending_.clear();
    }
}

std::optional<processing::ShownFramePtr> FrameProcessor::processGuarded(const Work& work) {
    std::optional<processing::ShownFramePtr> result;
    const Status done = base::guarded("processing failed", [&] { result = process(work); });
    if (done)
        return result;
    // What a stage left half made is not trusted: temporal state and remembered results start over.
    graph_.reset();
    ++failed_;
    // Logged when it first happens and when it changes, not for every frame of a failure that lasts.
    if (done.error().message != lastFailure_) {
        lastFailure_ = done.error().message;
        logError(lastFailure_ + " (the frame is skipped; later frames are processed)");
    }
    return std::nullopt;
}

std::optional<processing::ShownFramePtr> FrameProcessor::process(const Work& work) {
    if (work.reset) {
        graph_.reset();
        if (!work.session || (current_ && decodedBeforeSeek(*current_, work.awaitedSeek)))
            current_.reset();
    }
    bool fresh = false;
    bool taken = false;
    if (work.epoch != countedEpoch_) {
        // Another session: the old one's frame is not this source's to show, not even as a redo for a
        // demand that changes before the new source delivers (both sessions can reach one work item).
        current_.reset();
        countedEpoch_ = work.epoch;
        skipped_ = 0;
        failed_ = 0;
        lastFailure_.clear();
        pending_.clear();
    }
    if (work.frameSignal && work.session) {
        std::optional<frame::FramePtr> next = work.session->takeLatest();
        const bool got = next && *next; // before the frame is moved into current_
        const std::uint64_t sequence = got ? (*next)->sequence : 0;
        if (got && !decodedBeforeSeek(**next, work.awaitedSeek)) {
            // The same capture delivered again (a replay re-decoding it with its colour) is no new frame.
            fresh = !current_ || (*next)->timestampNs != current_->timestampNs;
            current_ = std::move(*next);
            taken = true;
        }
        if (got && !fresh) {
            ++skipped_;
            pending_.push_back({ProcessorRecord::Kind::Skipped, sequence, 0, 0});
        }
    }
    const bool changed = taken || work.reset || work.generation != lastGeneration_;
    if (!current_ || !changed)
        return std::nullopt;
    lastGeneration_ = work.generation;
    processing::ShownFramePtr shown = graph_.run(current_, work.demand, work.generation, fresh);
    for (const processing::StageTiming& t : shown->timings)
        stages_.add(t.name, t.milliseconds);
    accumulate(*shown, work.demand, fresh);
    return shown;
}

// Accumulation adds exactly the points the cloud shows: once per new frame, and the shown frame again when
// accumulation starts or its budget or voxel size changes (which starts it over), so that what it holds
// follows the settings at once, a paused replay's too.
void FrameProcessor::accumulate(const processing::ShownFrame& shown, const Demand& demand, bool fresh) {
    if (!demand.accumulate) {
        accumulatedWith_.reset();
        return;
    }
    const std::pair<std::size_t, float> with{demand.accumulateBudget, demand.accumulateVoxelMeters};
    if ((!fresh && accumulatedWith_ == with) || !shown.frame->pose || !shown.depth.data)
        return;
    accumulatedWith_ = with;
    accumulation_.submit({shown.depth.data, shown.depth.intrinsics, shown.pointColours, *shown.frame->pose,
                          demand.minConfidence, demand.nearMeters, demand.accumulateBudget,
                          demand.accumulateVoxelMeters});
}

void FrameProcessor::publish(processing::ShownFramePtr result, const Work& work) {
    if (result->newFrame) {
        ++counts_.framesProcessed;
        if (work.frameSignal)
            latencyMs_.add(std::chrono::duration<double, std::milli>(Clock::now() - work.arrival).count());
    } else {
        ++counts_.redone;
    }
    std::optional<std::uint64_t> unshown;
    results_.put(std::move(result),
                 [&unshown](const processing::ShownFramePtr& unseen, processing::ShownFramePtr& next) {
                     if (!unseen->newFrame)
                         return;
                     if (unseen->frame->timestampNs != next->frame->timestampNs) {
                         unshown = unseen->frame->sequence;
                     } else if (!next->newFrame) {
                         // A redo of a frame not yet taken: it is still that frame's first showing.
                         auto carried = std::make_shared<processing::ShownFrame>(*next);
                         carried->newFrame = true;
                         next = std::move(carried);
                     }
                 });
    if (unshown) {
        ++counts_.framesUnshown;
        addRecord({ProcessorRecord::Kind::Unshown, *unshown, 0, 0});
    }
}

void FrameProcessor::addRecord(ProcessorRecord record) {
    if (records_.size() == kMaxRecords)
        records_.pop_front();
    records_.push_back(record);
}

std::vector<ProcessorRecord> FrameProcessor::drainRecords() {
    base::MutexLock lock(mutex_);
    std::vector<ProcessorRecord> out(records_.begin(), records_.end());
    records_.clear();
    return out;
}

std::optional<processing::ShownFramePtr> FrameProcessor::take() {
    return results_.take();
}

std::optional<processing::ShownFramePtr>
FrameProcessor::waitFor(std::chrono::milliseconds timeout,
                        const std::function<bool(const processing::ShownFrame&)>& ready) {
    return results_.waitTake(timeout,
                             [&ready](const processing::ShownFramePtr& result) { return ready(*result); });
}

ProcessorCounts FrameProcessor::counts() const {
    base::MutexLock lock(mutex_);
    ProcessorCounts counts = counts_;
    counts.resultsTaken = results_.counts().taken;
    return counts;
}

base::RollingStats FrameProcessor::latencyMs() const {
    base::MutexLock lock(mutex_);
    return latencyMs_;
}

base::RollingStats FrameProcessor::cpuMs() const {
    base::MutexLock lock(mutex_);
    return cpuMs_;
}

std::uint64_t FrameProcessor::stageRuns(std::string_view stage) const {
    base::MutexLock lock(mutex_);
    const auto it = runs_.find(stage);
    return it == runs_.end() ? 0 : it->second;
}

} // namespace dc::engine
