#include "devices/session.h"

#include "base/clock.h"
#include "base/log.h"

namespace dc::devices {

namespace {
// Short enough that stop() returns promptly, long enough not to spin.
constexpr std::chrono::milliseconds kCaptureTimeout{50};
// How often a disconnected device looks for its camera again.
constexpr std::chrono::milliseconds kReconnectInterval{500};
} // namespace

Session::Session(std::unique_ptr<Device> device)
    : device_(std::move(device)), description_(device_->description()),
      capabilities_(device_->capabilities()) {}

Session::~Session() {
    stop();
}

Status Session::start() {
    if (capture_.joinable())
        return Error{"session for " + description_ + " is already running"};
    if (!capabilities_.sceneDepth)
        return Error{kNoDepthMessage};
    if (device_->state() == DeviceState::Closed) {
        if (Status s = device_->open(); !s)
            return s;
    }
    if (Status s = device_->start(); !s)
        return s;
    state_ = device_->state();
    push({SessionEvent::Kind::StateChanged, state_.load(),
          capabilities_.approximateIntrinsics ? kApproximateIntrinsicsMessage : ""});
    stopRequested_ = false;
    deliveries_ = {};
    capture_ = base::Worker("capture from " + description_, [this] { run(); });
    return {};
}

void Session::stop() {
    stopRequested_ = true;
    device_->interruptCapture();
    capture_.join();
    if (device_->state() != DeviceState::Closed) {
        (void)device_->stop();
        device_->close();
        state_ = device_->state();
    }
}

void Session::run() {
    // Nothing may escape a thread: an unexpected exception becomes an Error event and ends capture.
    try {
        while (!stopRequested_) {
            CaptureResult result = device_->capture(kCaptureTimeout);
            switch (result.kind) {
            case CaptureResult::Kind::Frame:
                onFrame(std::move(result.frame));
                break;
            case CaptureResult::Kind::Timeout:
                break;
            case CaptureResult::Kind::EndOfStream:
                push({SessionEvent::Kind::EndOfStream, device_->state(), "end of stream"});
                return;
            case CaptureResult::Kind::Disconnected:
                state_ = DeviceState::Disconnected;
                push({SessionEvent::Kind::StateChanged, DeviceState::Disconnected, result.message});
                if (!capabilities_.reconnects || !waitForReconnect())
                    return;
                break;
            case CaptureResult::Kind::Stalled:
                onStalled(result.message);
                break;
            case CaptureResult::Kind::Error:
                push({SessionEvent::Kind::Error, device_->state(), result.message});
                std::this_thread::sleep_for(kCaptureTimeout);
                break;
            }
        }
    } catch (const std::exception& e) {
        push(
            {SessionEvent::Kind::Error, device_->state(), std::string("capture thread failed: ") + e.what()});
    } catch (...) {
        push({SessionEvent::Kind::Error, device_->state(), "capture thread failed"});
    }
}

bool Session::waitForReconnect() {
    while (!stopRequested_) {
        if (device_->reconnect()) {
            state_ = DeviceState::Streaming;
            push({SessionEvent::Kind::StateChanged, DeviceState::Streaming, "reconnected"});
            return true;
        }
        for (auto waited = std::chrono::milliseconds(0); waited < kReconnectInterval && !stopRequested_;
             waited += kCaptureTimeout)
            std::this_thread::sleep_for(kCaptureTimeout);
    }
    return false;
}

void Session::onStalled(const std::string& message) {
    if (state_ == DeviceState::Stalled)
        return;
    state_ = DeviceState::Stalled;
    push({SessionEvent::Kind::StateChanged, DeviceState::Stalled, message});
}

std::optional<frame::FramePtr> Session::noteAge(std::optional<frame::FramePtr> frame) {
    const std::optional<std::int64_t> now = nowOnFrameClockNs(capabilities_);
    if (now && frame && *frame) {
        base::MutexLock lock(agesMutex_);
        ages_.add(frameAgeMs(**frame, *now));
    }
    return frame;
}

void Session::setFrameTap(std::function<void(const frame::FramePtr&)> tap) {
    base::MutexLock lock(tapMutex_);
    tap_ = std::move(tap);
}

void Session::setFrameListener(std::function<void()> listener) {
    base::MutexLock lock(tapMutex_);
    listener_ = std::move(listener);
}

void Session::onFrame(frame::FramePtr frame) {
    {
        base::MutexLock lock(tapMutex_);
        if (tap_)
            tap_(frame);
    }
    if (state_ == DeviceState::Stalled) {
        state_ = DeviceState::Streaming;
        push({SessionEvent::Kind::StateChanged, DeviceState::Streaming, "frames flow again"});
    }
    const std::int64_t arrivalNs = base::monotonicNowNs();
    const auto generation = [](const frame::Frame& f) { return f.replay ? f.replay->seekGeneration : 0; };
    record({FrameRecord::Kind::Delivered, frame->sequence, frame->timestampNs, frame->timing, arrivalNs,
            generation(*frame)});
    frames_.put(std::move(frame),
                [this, arrivalNs, generation](const frame::FramePtr& unseen, const frame::FramePtr&) {
                    record({FrameRecord::Kind::Replaced, unseen->sequence, unseen->timestampNs,
                            unseen->timing, arrivalNs, generation(*unseen)});
                });
    deliveries_.tick();
    deviceFps_ = deliveries_.perSecond();
    base::MutexLock lock(tapMutex_);
    if (listener_)
        listener_();
}

void Session::push(SessionEvent event) {
    if (event.kind == SessionEvent::Kind::Error)
        logError(description_ + ": " + event.message);
    base::MutexLock lock(eventsMutex_);
    events_.push_back(std::move(event));
}

void Session::record(FrameRecord record) {
    base::MutexLock lock(recordsMutex_);
    if (records_.size() == kMaxFrameRecords) {
        records_.pop_front();
        ++recordsLost_;
    }
    records_.push_back(std::move(record));
}

std::vector<FrameRecord> Session::drainFrameRecords() {
    base::MutexLock lock(recordsMutex_);
    std::vector<FrameRecord> out(std::make_move_iterator(records_.begin()),
                                 std::make_move_iterator(records_.end()));
    records_.clear();
    return out;
}

std::uint64_t Session::frameRecordsLost() const {
    base::MutexLock lock(recordsMutex_);
    return recordsLost_;
}

std::vector<SessionEvent> Session::drainEvents() {
    base::MutexLock lock(eventsMutex_);
    return std::exchange(events_, {});
}

SessionStats Session::stats() const {
    const base::LatestSlot<frame::FramePtr>::Counts frames = frames_.counts();
    base::MutexLock lock(agesMutex_);
    return {frames.put, frames.replaced, deviceFps_.load(), ages_.median()};
}

} // namespace dc::devices
