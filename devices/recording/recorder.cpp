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

std::vector<FrameEncoder> makeEncoders(const RecorderOptions& options) {
    std::vector<FrameEncoder> encoders;
    for (int i = 0; i < std::max(1, options.encoderThreads); ++i)
        encoders.emplace_back(options.writer.encode);
    return encoders;
}

} // namespace

Expected<std::unique_ptr<Recorder>> Recorder::start(const std::string& path, const DeviceInfo& device,
                                                    RecorderOptions options) {
    auto writer = RecordingWriter::create(path, device, options.writer);
    if (!writer)
        return writer.error();
    return std::unique_ptr<Recorder>(new Recorder(std::move(*writer), options));
}

Recorder::Recorder(RecordingWriter writer, const RecorderOptions& options)
    : path_(writer.path()), writer_(std::move(writer)), encodeFault_(options.encodeFault),
      encoders_(makeEncoders(options)),
      pool_(
          {"recording encoder", "encoding failed", encoders_.size(),
           std::max<std::size_t>(1, options.queueFrames)},
          [this](frame::FramePtr& frame, std::uint64_t number, std::size_t worker) {
              return encode(frame, number, worker);
          },
          [this](Expected<Encoded> encoded) { write(std::move(encoded)); }) {}

Recorder::~Recorder() {
    if (Status s = stop(); !s)
        logError(s.error().message);
}

bool Recorder::push(frame::FramePtr frame) {
    base::MutexLock lock(mutex_);
    if (stopping_ || failed_ || !pool_.trySubmit(std::move(frame))) {
        ++stats_.framesDropped;
        return false;
    }
    return true;
}

RecorderStats Recorder::stats() const {
    base::MutexLock lock(mutex_);
    RecorderStats stats = stats_;
    stats.queueDepth = pool_.pending();
    return stats;
}

void Recorder::fail(const std::string& message) {
    // Everything written so far stays readable in the partial file; nothing more is accepted.
    if (!failed_)
        stats_.error = message;
    failed_ = true;
    stats_.framesDropped += pool_.dropQueued();
}

Recorder::Encoded Recorder::encode(const frame::FramePtr& frame, std::uint64_t number, std::size_t worker) {
    const auto begin = std::chrono::steady_clock::now();
    if (encodeFault_)
        encodeFault_(number);
    Encoded result{frame->timestampNs, encoders_[worker].encode(*frame)};
    const double seconds = secondsSince(begin);
    base::MutexLock lock(mutex_);
    stats_.encodeSeconds += seconds;
    return result;
}

void Recorder::write(Expected<Encoded> encoded) {
    {
        base::MutexLock lock(mutex_);
        if (failed_) {
            ++stats_.framesDropped;
            return;
        }
    }
    const auto begin = std::chrono::steady_clock::now();
    // The encoder either threw (the pool's error) or returned an error.
    const Error* notEncoded = !encoded            ? &encoded.error()
                              : !encoded->payload ? &encoded->payload.error()
                                                  : nullptr;
    Status s = Status::success();
    if (notEncoded) {
        s = Error{path_ + ": frame " + std::to_string(writer_.framesWritten()) + ": " + notEncoded->message};
    } else {
        const Status ran = base::guarded(path_ + ": writing failed", [&] {
            s = writer_.appendEncoded(*encoded->payload, encoded->timestampNs);
        });
        if (!ran)
            s = ran;
    }
    const double seconds = secondsSince(begin);
    base::MutexLock lock(mutex_);
    stats_.writeSeconds += seconds;
    stats_.framesWritten = writer_.framesWritten();
    stats_.bytesWritten = writer_.bytesWritten();
    if (!s)
        fail(s.error().message);
}

Status Recorder::stop() {
    if (result_)
        return *result_;
    {
        base::MutexLock lock(mutex_);
        stopping_ = true;
    }
    pool_.finish();
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
