#pragma once

#include "devices/device.h"
#include "devices/replay/replay_source.h"

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dc::devices::replay {

struct ReplayOptions {
    bool loop = false;
    double speed = 1.0;
    bool startPlaying = true;
};

struct ReplayStatus {
    std::size_t index = 0; // the frame delivered last (or being delivered after a seek)
    std::size_t count = 0;
    std::int64_t timestampNs = 0;      // of that frame
    std::int64_t firstTimestampNs = 0; // the recording's time span, for a timeline
    std::int64_t lastTimestampNs = 0;
    bool playing = false;
    bool loop = false;
    double speed = 1.0;
    bool atEnd = false;               // paused on the last frame because loop is off
    std::uint64_t seekGeneration = 0; // the generation of the latest seek or step requested
    std::uint64_t framesSkipped = 0;  // frames that failed to decode and were skipped
    std::uint64_t colorDecodes = 0;   // frames delivered with their camera image decoded
    std::string lastProblem;          // why the last skipped frame failed
};

// The index of the timestamp nearest `timestampNs` (the earlier one of two as near) in ascending
// `timestampsNs` (0 when empty): the frame a replay that follows another's clock shows
// (ReplayControl::seekToNearestTime), and the one a fused export pairs.
std::size_t nearestTimeIndex(const std::vector<std::int64_t>& timestampsNs, std::int64_t timestampNs);

// The timeline of a replay, held by the UI. Every method is thread-safe and returns at once; the replay
// device applies the request on its capture thread. Seeks are exact: seekToIndex(), seekToTime() and
// step() return a generation number, and the first frame whose Frame::replay->seekGeneration is at least
// that number is the frame asked for (frames with an older generation were decoded before the request).
class ReplayControl {
public:
    static constexpr double kMinSpeed = 0.25;
    static constexpr double kMaxSpeed = 4.0;

    void play();
    void pause();
    void setLoop(bool loop);
    void setSpeed(double speed);                  // clamped to [kMinSpeed, kMaxSpeed]
    std::uint64_t seekToIndex(std::size_t index); // clamped to the recording; pauses nothing
    std::uint64_t seekToTime(std::int64_t timestampNs);
    // The frame whose timestamp is nearest (the earlier one of two as near): how a replay follows another's
    // clock.
    std::uint64_t seekToNearestTime(std::int64_t timestampNs);
    std::uint64_t step(int frames); // pauses, then moves by `frames` (negative: backwards)
    ReplayStatus status() const;
    // Every frame's timestamp, in order: fixed for the replay's life, so read without the lock (another
    // replay's frames are placed on this one's timeline by them).
    const std::vector<std::int64_t>& timestampsNs() const { return timestampsNs_; }

private:
    friend class ReplayDevice;
    struct Seek {
        std::size_t index = 0;
        std::uint64_t generation = 0;
    };

    ReplayControl(std::vector<std::int64_t> timestampsNs, const ReplayOptions& options);
    std::uint64_t requestSeek(std::size_t index); // with mutex_ held

    const std::vector<std::int64_t> timestampsNs_; // a copy, so the control outlives the device
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    ReplayStatus status_;
    std::optional<Seek> pendingSeek_;
    std::uint64_t changes_ = 0; // bumped by every request, so the device notices any of them
    bool wantColor_ = true;     // the consumers' SourceDemand::cameraImage
    bool refresh_ = false;      // deliver the current frame again (now with its colour)
};

// Plays a ReplaySource through the Device interface, paced by the recorded timestamps (scaled by the
// speed), so a replay reaches the viewer through the same Session as a live camera. At the end it pauses
// on the last frame unless loop is on; it never ends the stream, so the timeline stays usable.
class ReplayDevice final : public Device {
public:
    explicit ReplayDevice(std::unique_ptr<ReplaySource> source, ReplayOptions options = {});

    std::string description() const override { return source_->description(); }
    Capabilities capabilities() const override { return source_->capabilities(); }
    // Shared with the UI; stays valid after the device is gone.
    std::shared_ptr<ReplayControl> control() const { return control_; }
    // Frames decoded from now on carry their camera image only when it is wanted. When it becomes wanted
    // again while paused on a frame decoded without it, that frame is decoded again, exactly, and delivered
    // once more (same index, same seek generation).
    void setDemand(const SourceDemand& demand) override;

protected:
    Status doOpen() override;
    Status doStart() override;
    void doStop() override {}
    CaptureResult doCapture(std::chrono::milliseconds timeout) override;

private:
    using Clock = std::chrono::steady_clock;

    // Decodes `index` or, when it is damaged, the next readable frame after it (skips are counted).
    std::optional<std::pair<std::size_t, frame::Frame>> decodeFrom(std::size_t index);
    CaptureResult deliver(std::size_t index, frame::Frame frame, std::uint64_t generation);
    Clock::time_point dueTime(std::size_t next, double speed) const;
    std::optional<CaptureResult> playNext(std::unique_lock<std::mutex>& lock, Clock::time_point deadline);

    std::unique_ptr<ReplaySource> source_;
    std::shared_ptr<ReplayControl> control_;
    std::uint64_t delivered_ = 0;
    std::uint64_t appliedGeneration_ = 0;
    bool wasPlaying_ = false;
    // Pacing: the current frame was due at lastDue_; the next follows at the recorded spacing.
    Clock::time_point lastDue_;
    bool lastHadColor_ = true; // whether the frame delivered last carried its camera image
};

} // namespace dc::devices::replay
