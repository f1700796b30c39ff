#include "engine/instrument.h"

#include "base/clock.h"
#include "base/log.h"
#include "devices/frame_age.h"
#include "devices/recording/take_names.h"
#include "devices/source_spec.h"

#include <algorithm>

namespace dc::engine {

namespace {

using Clock = std::chrono::steady_clock;
// Rates are counted over this much recent time: long enough to be steady, short enough to fall to zero
// soon after a source pauses or ends.
constexpr std::chrono::milliseconds kRateWindow{1000};

} // namespace

Instrument::Instrument(std::unique_ptr<devices::Device> device, std::string spec)
    : spec_(std::move(spec)), processor_(std::make_unique<FrameProcessor>(stages_, accumulation_)) {
    adoptReplay(*device);
    session_ = std::make_shared<devices::Session>(std::move(device));
}

Instrument::~Instrument() {
    exportJob_.reset();
    if (recording_)
        (void)stopRecording();
    session_->stop();
    processor_.reset();
}

// A replay hands the UI its timeline; every other source has none.
void Instrument::adoptReplay(devices::Device& device) {
    const auto* replay = dynamic_cast<const devices::replay::ReplayDevice*>(&device);
    replay_ = replay ? replay->control() : nullptr;
}

std::string SourceState::text() const {
    switch (note) {
    case Note::None:
        break;
    case Note::EndOfStream:
        return "end of stream";
    case Note::Paused:
        return "paused";
    case Note::Ended:
        return "ended";
    }
    return devices::toString(device);
}

void Instrument::start() {
    startSession();
}

void Instrument::startSession() {
    message_.clear();
    state_ = {};
    // Before the capture thread starts, so that not even the first frame decodes what nobody shows.
    session_->setDemand({demand_.needsCameraImage()});
    if (Status s = session_->start(); !s) {
        message_ = s.error().message;
        running_ = false;
        logError(session_->description() + ": " + message_);
        return;
    }
    running_ = true;
    processor_->setSession(session_);
}

Status Instrument::openSource(const std::string& spec) {
    auto device = devices::openSourceSpec(spec);
    if (!device) {
        logError(spec + ": " + device.error().message);
        return device.error();
    }
    switchSource(std::move(*device), spec);
    return {};
}

void Instrument::switchSource(std::unique_ptr<devices::Device> device, std::string spec) {
    if (recording_)
        (void)stopRecording();
    processor_->setSession(nullptr);
    session_->stop();
    adoptReplay(*device);
    session_ = std::make_shared<devices::Session>(std::move(device));
    spec_ = std::move(spec);
    // Another source means another world: nothing measured in the old one carries over.
    accumulation_.clear();
    stages_.clear();
    latencyMs_ = base::RollingStats();
    timing_.reset();
    shown_ = 0;
    handedOut_.reset();
    countHistory_.clear();
    lastShownTimestampNs_ = ~0ull;
    startSession();
    logInfo("source: " + session_->description());
}

std::uint64_t Instrument::setDemand(const Demand& demand) {
    if (!(demand.needsCameraImage() == demand_.needsCameraImage()) && running_)
        session_->setDemand({demand.needsCameraImage()});
    demand_ = demand;
    demandGeneration_ = processor_->setDemand(demand);
    return demandGeneration_;
}

std::optional<processing::ShownFramePtr> Instrument::update() {
    drainEvents();
    drainTiming();
    return handOut(processor_->take());
}

std::optional<processing::ShownFramePtr>
Instrument::handOut(std::optional<processing::ShownFramePtr> result) {
    if (result)
        handedOut_ = *result;
    return result;
}

std::optional<processing::ShownFramePtr> Instrument::waitForResult(std::chrono::milliseconds timeout,
                                                                   bool newFrame) {
    drainEvents();
    const std::uint64_t generation = demandGeneration_;
    const std::uint64_t last = lastShownTimestampNs_;
    return handOut(processor_->waitFor(timeout, [&](const processing::ShownFrame& shown) {
        const bool answers = shown.demandGeneration >= generation;
        const bool unseen = static_cast<std::uint64_t>(shown.frame->timestampNs) != last;
        return answers && (!newFrame || (shown.newFrame && unseen));
    }));
}

void Instrument::presented(const processing::ShownFrame& shown) {
    if (!shown.newFrame || &shown != handedOut_.get())
        return;
    ++shown_;
    lastShownTimestampNs_ = static_cast<std::uint64_t>(shown.frame->timestampNs);
    // The records of the frame shown were made before its result could be taken: all are here now.
    drainTiming();
    timing_.shown(shown.frame->sequence, base::monotonicNowNs());
    // Only sources stamping frames with a clock of this machine have a latency; a recording's clock has none.
    if (const auto now = devices::nowOnFrameClockNs(session_->capabilities()))
        latencyMs_.add(devices::frameAgeMs(*shown.frame, *now));
}

void Instrument::drainTiming() {
    // The processor's first: every frame they name was delivered before they were drained, so the session's
    // records, drained after, hold its delivery, which the model must see first.
    const std::vector<ProcessorRecord> processed = processor_->drainRecords();
    for (const devices::FrameRecord& r : session_->drainFrameRecords())
        timing_.add(r);
    for (const ProcessorRecord& r : processed)
        timing_.add(r);
}

TimingSummary Instrument::timing() {
    drainTiming();
    TimingSummary t = timing_.summary();
    t.recordsLost = session_->frameRecordsLost();
    return t;
}

void Instrument::drainEvents() {
    for (const devices::SessionEvent& e : session_->drainEvents()) {
        state_ = {e.state, e.kind == devices::SessionEvent::Kind::EndOfStream ? SourceState::Note::EndOfStream
                                                                              : SourceState::Note::None};
        if (!e.message.empty())
            message_ = e.message;
    }
}

FrameCounts Instrument::countFrames() {
    // The processor's counts first: every frame they count was delivered before the session's count is
    // read, so shown + dropped never exceeds delivered, however the threads interleave.
    const ProcessorCounts processor = processor_->counts();
    const devices::SessionStats session = session_->stats();
    FrameCounts c{session.framesCaptured, shown_,
                  session.framesDropped + processor.framesUnshown + processor.framesSkipped, 0.0, 0.0};
    const auto now = Clock::now();
    countHistory_.push_back({now, c.delivered, c.shown});
    while (countHistory_.size() > 2 && now - countHistory_[1].at >= kRateWindow)
        countHistory_.pop_front();
    const CountSample& first = countHistory_.front();
    const double seconds = std::chrono::duration<double>(now - first.at).count();
    if (seconds > 0.0) {
        c.deliveredPerSecond = static_cast<double>(c.delivered - first.delivered) / seconds;
        c.shownPerSecond = static_cast<double>(c.shown - first.shown) / seconds;
    }
    return c;
}

InstrumentStatus Instrument::status() {
    drainEvents();
    InstrumentStatus s{session_->description(), state_,       message_,     running_,
                       countFrames(),           std::nullopt, std::nullopt, stages_.recent()};
    s.unregisteredColour = session_->capabilities().unregisteredColour;
    if (replay_ && running_) {
        const devices::replay::ReplayStatus r = replay_->status();
        if (r.atEnd && !r.loop)
            s.state.note = SourceState::Note::Ended;
        else if (!r.playing)
            s.state.note = SourceState::Note::Paused;
    }
    if (latencyMs_.count() > 0)
        s.latencyMs = latencyMs_.median();
    return s;
}

void Instrument::seekReplay(std::size_t index) {
    if (replay_)
        processor_->afterSeek(replay_->seekToIndex(index));
}

void Instrument::seekReplayNear(std::int64_t timestampNs) {
    if (replay_)
        processor_->afterSeek(replay_->seekToNearestTime(timestampNs));
}

void Instrument::stepReplay(int frames) {
    if (replay_)
        processor_->afterSeek(replay_->step(frames));
}

Status Instrument::startRecording(const std::string& path,
                                  const devices::recording::RecordingOptions& options) {
    if (recording_)
        return Error{"already recording to " + recording_->path()};
    auto r = devices::recording::SessionRecording::start(*session_, path, options);
    if (!r) {
        logError("record: " + r.error().message);
        return r.error();
    }
    recording_ = std::move(*r);
    recordingOptions_ = options;
    recordingStarted_ = Clock::now();
    logInfo("recording to " + path);
    return {};
}

Expected<std::string> Instrument::startTake(const std::string& directory,
                                            const devices::recording::RecordingOptions& options) {
    auto path = devices::recording::nextTakePath(directory);
    if (!path) {
        logError("record: " + path.error().message);
        return path.error();
    }
    if (Status s = startRecording(*path, options); !s)
        return s.error();
    return *path;
}

Status Instrument::stopRecording() {
    if (!recording_)
        return {};
    Status s = recording_->stop();
    const devices::recording::RecorderStats stats = recording_->stats();
    const std::string path = recording_->path();
    recording_.reset();
    if (!s) {
        logError("recording " + path + ": " + s.error().message);
        return s;
    }
    logNotice("recorded " + std::to_string(stats.framesWritten) + " frames (" +
              std::to_string(stats.framesDropped) + " dropped) to " + path);
    return {};
}

RecordingStatus Instrument::recording() const {
    if (!recording_)
        return {};
    const devices::recording::RecorderStats s = recording_->stats();
    // Frames accepted are written or about to be: the same count the final message gives once they are.
    return {true,
            recording_->path(),
            s.framesWritten + s.queueDepth,
            s.framesDropped,
            s.bytesWritten,
            recordingOptions_,
            recordingStarted_};
}

Status Instrument::startExport(exporting::ExportFormat format, const std::string& directory,
                               std::size_t first, std::size_t end, const Demand& demand) {
    if (!replay_)
        return Error{"export needs a replay source"};
    if (exportJob_ && !exportJob_->finished())
        return Error{"an export is already running"};
    exporting::ExportOptions options;
    options.format = format;
    options.outDirectory = directory;
    options.frames = {first, end};
    options.transform = processedDepth(demand);
    auto job = ExportJob::start(spec_, options);
    if (!job) {
        logError("export: " + job.error().message);
        return job.error();
    }
    exportJob_ = std::move(*job);
    return {};
}

} // namespace dc::engine
