#include "devices/recording/recorder.h"

#include "base/barrier.h"
#include "base/log.h"

#include <algorithm>
#include <chrono>

namespace dc::devices::recording {

namespace {
double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
} // namespace

Expected<std::unique_ptr<Recorder>> Recorder::start(const std::string& path, const DeviceInfo& device,
                                                    RecorderOptions options) {
    auto writer = RecordingWriter::create(path, device, options.writer);
    if (!writer)
        return writer.error();
    std::unique_ptr<Recorder> recorder(new Recorder(std::move(*writer), options));
    Recorder* r = recorder.get();
    const int encoders = std::max(1, options.encoderThreads);
    {
        base::MutexLock lock(r->mutex_);
        r->encodersRunning_ = encoders;
    }
    for (int i = 0; i < encoders; ++i)
        r->encoders_.emplace_back("recording encoder",
                                  [r, encode = options.writer.encode] { r->encodeLoop(encode); });
    r->writerThread_ = base::Worker("recording writer", [r] { r->writeLoop(); });
    return recorder;
}

Recorder::Recorder(RecordingWriter writer, const RecorderOptions& options)
    : path_(writer.path()), writer_(std::move(writer)),
      capacity_(std::max<std::size_t>(1, options.queueFrames)), encodeFault_(options.encodeFault) {}

Recorder::~Recorder() {
    if (Status s = stop(); !s)
        logError(s.error().message);
}

bool Recorder::push(frame::FramePtr frame) {
    {
        base::MutexLock lock(mutex_);
        if (stopping_ || failed_ || inFlight_ >= capacity_) {
            ++stats_.framesDropped;
            return false;
        }
        pending_.emplace_back(nextSequence_++, std::move(frame));
        stats_.queueDepth = ++inFlight_;
    }
    work_.notify_one();
    return true;
}

RecorderStats Recorder::stats() const {
    base::MutexLock lock(mutex_);
    return stats_;
}

void Recorder::fail(const std::string& message) {
    // Everything written so far stays readable in the partial file; nothing more is accepted.
    if (!failed_)
        stats_.error = message;
    failed_ = true;
    stats_.framesDropped += pending_.size();
    pending_.clear();
}

void Recorder::encodeLoop(EncodeOptions options) {
    FrameEncoder encoder(options);
    base::MutexLock lock(mutex_);
    for (;;) {
        lock.wait(work_, [this]() DC_REQUIRES(mutex_) { return stopping_ || failed_ || !pending_.empty(); });
        if (pending_.empty())
            break;
        auto [sequence, frame] = std::move(pending_.front());
        pending_.pop_front();
        lock.unlock();
        const auto begin = std::chrono::steady_clock::now();
        Encoded result{frame->timestampNs, Error{"not encoded"}};
        const auto& captured = *frame; // a lambda may not capture a structured binding (clang 14)
        const std::uint64_t number = sequence;
        const Status ran = base::guarded("encoding failed", [&] {
            if (encodeFault_)
                encodeFault_(number);
            result.payload = encoder.encode(captured);
        });
        if (!ran)
            result.payload = ran.error();
        frame.reset();
        const double seconds = secondsSince(begin);
        lock.lock();
        stats_.encodeSeconds += seconds;
        encoded_.emplace(sequence, std::move(result));
        written_.notify_one();
    }
    --encodersRunning_;
    written_.notify_one();
}

void Recorder::writeLoop() {
    base::MutexLock lock(mutex_);
    for (;;) {
        lock.wait(written_, [this]() DC_REQUIRES(mutex_) {
            return encoded_.contains(nextToWrite_) || encodersRunning_ == 0;
        });
        const auto next = encoded_.find(nextToWrite_);
        if (next == encoded_.end())
            return; // the encoders have ended and everything they made is written
        Encoded item = std::move(next->second);
        encoded_.erase(next);
        ++nextToWrite_;
        if (failed_) {
            --inFlight_;
            ++stats_.framesDropped;
            continue;
        }
        lock.unlock();
        const auto begin = std::chrono::steady_clock::now();
        Status s = Error{path_ + ": frame " + std::to_string(writer_.framesWritten()) + ": " +
                         (item.payload ? "" : item.payload.error().message)};
        if (item.payload) {
            const Status ran = base::guarded(path_ + ": writing failed", [&] {
                s = writer_.appendEncoded(*item.payload, item.timestampNs);
            });
            if (!ran)
                s = ran;
        }
        const double seconds = secondsSince(begin);
        lock.lock();
        stats_.writeSeconds += seconds;
        stats_.framesWritten = writer_.framesWritten();
        stats_.bytesWritten = writer_.bytesWritten();
        stats_.queueDepth = --inFlight_;
        if (!s) {
            fail(s.error().message);
            work_.notify_all();
        }
    }
}

Status Recorder::stop() {
    if (result_)
        return *result_;
    {
        base::MutexLock lock(mutex_);
        stopping_ = true;
    }
    work_.notify_all();
    for (base::Worker& t : encoders_)
        t.join();
    writerThread_.join();
    base::MutexLock lock(mutex_);
    if (failed_) {
        result_ = Error{stats_.error + " (the frames written before are in " + writer_.partialPath() + ")"};
    } else {
        result_ = writer_.finish();
        stats_.bytesWritten = writer_.bytesWritten();
    }
    return *result_;
}

} // namespace dc::devices::recording
