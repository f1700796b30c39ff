#include "devices/replay/replay_device.h"

#include "base/log.h"

#include <algorithm>
#include <cmath>

namespace dc::devices::replay {

namespace {
// A pause in the recording longer than this plays as this long: nobody wants to watch a gap.
constexpr std::chrono::nanoseconds kMaxGap = std::chrono::seconds(1);
// Later than this behind schedule (slow decoding), playback resumes from now instead of bursting.
constexpr std::chrono::milliseconds kMaxLateness{100};
} // namespace

ReplayControl::ReplayControl(std::vector<std::int64_t> timestampsNs, const ReplayOptions& options)
    : timestampsNs_(std::move(timestampsNs)) {
    status_.count = timestampsNs_.size();
    status_.firstTimestampNs = timestampsNs_.empty() ? 0 : timestampsNs_.front();
    status_.lastTimestampNs = timestampsNs_.empty() ? 0 : timestampsNs_.back();
    status_.timestampNs = status_.firstTimestampNs;
    status_.loop = options.loop;
    status_.speed = std::clamp(options.speed, kMinSpeed, kMaxSpeed);
    status_.playing = options.startPlaying;
    pendingSeek_ = Seek{0, 0}; // the first frame is delivered at once, playing or not
}

std::uint64_t ReplayControl::requestSeek(std::size_t index) {
    index = std::min(index, status_.count == 0 ? 0 : status_.count - 1);
    pendingSeek_ = Seek{index, ++status_.seekGeneration};
    status_.index = index;
    status_.timestampNs = status_.count == 0 ? 0 : timestampsNs_[index];
    status_.atEnd = false;
    ++changes_;
    changed_.notify_all();
    return status_.seekGeneration;
}

void ReplayControl::play() {
    std::lock_guard lock(mutex_);
    if (status_.atEnd)
        requestSeek(0); // play at the end starts over, as media players do
    status_.playing = true;
    ++changes_;
    changed_.notify_all();
}

void ReplayControl::pause() {
    std::lock_guard lock(mutex_);
    status_.playing = false;
    ++changes_;
    changed_.notify_all();
}

void ReplayControl::setLoop(bool loop) {
    std::lock_guard lock(mutex_);
    status_.loop = loop;
    ++changes_;
    changed_.notify_all();
}

void ReplayControl::setSpeed(double speed) {
    std::lock_guard lock(mutex_);
    status_.speed = std::clamp(std::isfinite(speed) ? speed : 1.0, kMinSpeed, kMaxSpeed);
    ++changes_;
    changed_.notify_all();
}

std::uint64_t ReplayControl::seekToIndex(std::size_t index) {
    std::lock_guard lock(mutex_);
    return requestSeek(index);
}

std::uint64_t ReplayControl::seekToTime(std::int64_t timestampNs) {
    std::lock_guard lock(mutex_);
    // The frame on screen at that time: the last one not after it.
    const auto after = std::upper_bound(timestampsNs_.begin(), timestampsNs_.end(), timestampNs);
    const auto index =
        static_cast<std::size_t>(after == timestampsNs_.begin() ? 0 : after - timestampsNs_.begin() - 1);
    return requestSeek(index);
}

std::size_t nearestTimeIndex(const std::vector<std::int64_t>& timestampsNs, std::int64_t timestampNs) {
    const auto after = std::lower_bound(timestampsNs.begin(), timestampsNs.end(), timestampNs);
    auto index = static_cast<std::size_t>(after - timestampsNs.begin());
    if (after == timestampsNs.end() ||
        (after != timestampsNs.begin() && timestampNs - *(after - 1) <= *after - timestampNs))
        index = index == 0 ? 0 : index - 1;
    return index;
}

std::uint64_t ReplayControl::seekToNearestTime(std::int64_t timestampNs) {
    std::lock_guard lock(mutex_);
    return requestSeek(nearestTimeIndex(timestampsNs_, timestampNs));
}

std::uint64_t ReplayControl::step(int frames) {
    std::lock_guard lock(mutex_);
    status_.playing = false;
    const std::size_t from = pendingSeek_ ? pendingSeek_->index : status_.index;
    const auto target = static_cast<std::ptrdiff_t>(from) + frames;
    return requestSeek(static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, target)));
}

ReplayStatus ReplayControl::status() const {
    std::lock_guard lock(mutex_);
    return status_;
}

// ---------------------------------------------------------------------------------------------------

ReplayDevice::ReplayDevice(std::unique_ptr<ReplaySource> source, ReplayOptions options)
    : source_(std::move(source)) {
    std::vector<std::int64_t> timestamps(source_->frameCount());
    for (std::size_t i = 0; i < timestamps.size(); ++i)
        timestamps[i] = source_->timestampNs(i);
    control_.reset(new ReplayControl(std::move(timestamps), options));
}

Status ReplayDevice::doOpen() {
    if (source_->frameCount() == 0)
        return Error{source_->description() + " holds no frames (zero-frame recording)"};
    return {};
}

Status ReplayDevice::doStart() {
    lastDue_ = Clock::now();
    return {};
}

void ReplayDevice::setDemand(const SourceDemand& demand) {
    std::lock_guard lock(control_->mutex_);
    if (control_->wantColor_ == demand.cameraImage)
        return;
    control_->wantColor_ = demand.cameraImage;
    if (demand.cameraImage && !lastHadColor_ && !control_->status_.playing && capabilities().color &&
        delivered_ > 0) {
        control_->refresh_ = true;
        ++control_->changes_;
        control_->changed_.notify_all();
    }
}

namespace {

// Bad frames in a row are reported one by one up to a few, then once in a summary: a recording whose files
// vanished mid-replay would otherwise say the same thing for each of its hundreds of frames.
class SkipReport {
public:
    static constexpr std::size_t kEachUpTo = 3;

    void add(std::size_t index, const std::string& problem) {
        if (skipped_ < kEachUpTo)
            logWarning("replay: skipping a bad frame: " + problem);
        else
            last_ = {index, problem};
        ++skipped_;
    }
    ~SkipReport() {
        if (skipped_ > kEachUpTo)
            logWarning("replay: skipped " + std::to_string(skipped_ - kEachUpTo) +
                       " more bad frames in a row, up to " + "frame " + std::to_string(last_.first) + ": " +
                       last_.second);
    }

private:
    std::size_t skipped_ = 0;
    std::pair<std::size_t, std::string> last_;
};

} // namespace

std::optional<std::pair<std::size_t, frame::Frame>> ReplayDevice::decodeFrom(std::size_t index) {
    {
        std::lock_guard lock(control_->mutex_);
        source_->setDecodeColor(control_->wantColor_);
    }
    const std::size_t count = source_->frameCount();
    SkipReport skips;
    for (std::size_t tried = 0; tried < count; ++tried) {
        auto frame = loadFrame(*source_, index);
        if (frame)
            return std::pair{index, std::move(*frame)};
        skips.add(index, frame.error().message);
        {
            std::lock_guard lock(control_->mutex_);
            ++control_->status_.framesSkipped;
            control_->status_.lastProblem = frame.error().message;
        }
        if (index + 1 >= count)
            return std::nullopt;
        ++index;
    }
    return std::nullopt;
}

CaptureResult ReplayDevice::deliver(std::size_t index, frame::Frame frame, std::uint64_t generation) {
    ReplayStatus& status = control_->status_;
    status.index = index;
    status.timestampNs = source_->timestampNs(index);
    frame.sequence = delivered_++;
    frame.replay = frame::ReplayPosition{index, source_->frameCount(), generation};
    // The recorded sensor stamps are another run's clock: compared with this one's arrival and display times
    // they would give latencies of hours.
    frame.timing.depth.monotonic = false;
    if (frame.timing.colour)
        frame.timing.colour->monotonic = false;
    lastHadColor_ = !frame.capturedImage.empty();
    status.colorDecodes += lastHadColor_ ? 1 : 0;
    return {CaptureResult::Kind::Frame, std::make_shared<const frame::Frame>(std::move(frame)), {}};
}

ReplayDevice::Clock::time_point ReplayDevice::dueTime(std::size_t next, double speed) const {
    const std::size_t current = next == 0 ? 0 : next - 1;
    const auto gap = std::chrono::nanoseconds(std::clamp<std::int64_t>(
        source_->timestampNs(next) - source_->timestampNs(current), 0, kMaxGap.count()));
    return lastDue_ + std::chrono::duration_cast<Clock::duration>(gap / speed);
}

CaptureResult ReplayDevice::doCapture(std::chrono::milliseconds timeout) {
    ReplayControl& c = *control_;
    const auto deadline = Clock::now() + timeout;
    std::unique_lock lock(c.mutex_);
    for (;;) {
        if (c.pendingSeek_) {
            const ReplayControl::Seek seek = *std::exchange(c.pendingSeek_, std::nullopt);
            lock.unlock();
            auto decoded = decodeFrom(seek.index);
            lock.lock();
            if (c.pendingSeek_)
                continue; // a newer request came while decoding: that one is what the user wants now
            if (!decoded)
                return {CaptureResult::Kind::Error, nullptr,
                        source_->description() + ": no readable frame from " + std::to_string(seek.index) +
                            " on"};
            appliedGeneration_ = seek.generation;
            lastDue_ = Clock::now();
            return deliver(decoded->first, std::move(decoded->second), seek.generation);
        }
        if (std::exchange(c.refresh_, false)) {
            const std::size_t index = c.status_.index;
            lock.unlock();
            auto decoded = decodeFrom(index);
            lock.lock();
            if (decoded && !c.pendingSeek_)
                return deliver(decoded->first, std::move(decoded->second), appliedGeneration_);
            continue;
        }
        if (c.status_.playing) {
            if (auto result = playNext(lock, deadline))
                return std::move(*result);
            continue;
        }
        wasPlaying_ = false;
        const std::uint64_t changes = c.changes_;
        if (!c.changed_.wait_until(lock, deadline, [&] { return c.changes_ != changes; }))
            return {CaptureResult::Kind::Timeout, nullptr, {}};
    }
}

// One step of playback with the control's mutex held: waits for the next frame's time and delivers it,
// or reports Timeout at the deadline. Empty: the control state changed, the caller looks again.
std::optional<CaptureResult> ReplayDevice::playNext(std::unique_lock<std::mutex>& lock,
                                                    Clock::time_point deadline) {
    ReplayControl& c = *control_;
    const auto now = Clock::now();
    if (!wasPlaying_ || now - lastDue_ > std::chrono::seconds(2))
        lastDue_ = now; // resumed: the next frame follows from now
    wasPlaying_ = true;
    std::size_t next = c.status_.index + 1;
    if (next >= source_->frameCount()) {
        if (!c.status_.loop) {
            c.status_.playing = false;
            c.status_.atEnd = true;
            return std::nullopt;
        }
        next = 0;
    }
    auto due = next == 0 ? now : dueTime(next, c.status_.speed);
    if (now - due > kMaxLateness)
        due = now;
    const std::uint64_t changes = c.changes_;
    const auto changed = [&] { return c.changes_ != changes; };
    if (c.changed_.wait_until(lock, std::min(due, deadline), changed))
        return std::nullopt;
    if (due > deadline)
        return CaptureResult{CaptureResult::Kind::Timeout, nullptr, {}};
    lock.unlock();
    auto decoded = decodeFrom(next);
    lock.lock();
    if (c.pendingSeek_ || !c.status_.playing)
        return std::nullopt;
    if (!decoded) {
        c.status_.index = source_->frameCount() - 1; // everything after `next` was unreadable
        return std::nullopt;
    }
    lastDue_ = due;
    return deliver(decoded->first, std::move(decoded->second), appliedGeneration_);
}

} // namespace dc::devices::replay
