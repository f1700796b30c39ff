#pragma once

#include "base/latest_slot.h"
#include "base/mutex.h"
#include "base/rate_meter.h"
#include "base/rolling_stats.h"
#include "base/worker.h"
#include "devices/device.h"
#include "devices/frame_age.h"

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace dc::devices {

// Something the UI should know about, queued by the capture thread and drained once per UI frame.
struct SessionEvent {
    enum class Kind { StateChanged, Error, EndOfStream };
    Kind kind = Kind::StateChanged;
    DeviceState state = DeviceState::Closed;
    std::string message;
};

struct SessionStats {
    std::uint64_t framesCaptured = 0;
    std::uint64_t framesDropped = 0; // replaced in the slot before any consumer took them
    double deviceFps = 0.0;          // delivery rate measured on the capture thread
    // Median age of the frames consumers took (now - timestampNs at take), for devices whose timestamps are
    // capture times on a clock of this machine (Capabilities::monotonicTimestamps or realtimeTimestamps); 0
    // for the others.
    double latencyMs = 0.0;
};

// One frame's passage through the session, for the timing view (engine::TimingModel): delivered by the
// device, or replaced in the latest-wins slot by a newer frame before any consumer took it.
struct FrameRecord {
    enum class Kind { Delivered, Replaced };
    Kind kind = Kind::Delivered;
    std::uint64_t sequence = 0;   // Frame::sequence
    std::int64_t timestampNs = 0; // Frame::timestampNs
    frame::FrameTiming timing;
    std::int64_t atNs = 0; // CLOCK_MONOTONIC when it happened: for Delivered, the frame's arrival
    // A replay's seek generation (frame::ReplayPosition), 0 for live sources: a seek makes the driver's
    // recorded sequence jump, which is no frame lost.
    std::uint64_t seekGeneration = 0;
};

// Runs one device on its own capture thread. The thread only captures and posts: frames reach consumers
// through a latest-wins slot, state changes and errors through an event queue.
class Session {
public:
    static constexpr const char* kNoDepthMessage = "Unsupported device: this source provides no depth";

    explicit Session(std::unique_ptr<Device> device);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Opens and starts the device and the capture thread. A device without scene depth is refused with
    // kNoDepthMessage (the sample's "Unsupported device").
    Status start();
    void stop();

    std::optional<frame::FramePtr> takeLatest() { return noteAge(frames_.take()); }
    std::optional<frame::FramePtr> waitForFrame(std::chrono::milliseconds timeout) {
        return noteAge(frames_.waitTake(timeout));
    }
    std::vector<SessionEvent> drainEvents();
    // What happened to each frame since the last call, in order. At most kMaxFrameRecords are kept: a
    // session nobody drains (a headless recording) keeps the newest, and frameRecordsLost() counts the rest.
    std::vector<FrameRecord> drainFrameRecords();
    std::uint64_t frameRecordsLost() const;
    static constexpr std::size_t kMaxFrameRecords = 4096;

    SessionStats stats() const;
    // Called on the capture thread with every frame before it is posted (a recorder's push). The tap
    // must return at once; an empty function removes it. Thread-safe.
    void setFrameTap(std::function<void(const frame::FramePtr&)> tap);
    // Called on the capture thread after each frame is posted, so a consumer waiting on something else
    // too (the frame processor) can wake up and take it. Must return at once; empty removes it. Thread-safe.
    void setFrameListener(std::function<void()> listener);
    // Forwarded to the device (Device::setDemand); thread-safe.
    void setDemand(const SourceDemand& demand) { device_->setDemand(demand); }
    // Forwarded to the device (Device::sensorControls); thread-safe.
    std::shared_ptr<SensorControls> sensorControls() const { return device_->sensorControls(); }
    DeviceState state() const { return state_.load(); }
    const std::string& description() const { return description_; }
    const Capabilities& capabilities() const { return capabilities_; }

private:
    void run();
    void onFrame(frame::FramePtr frame);
    void onStalled(const std::string& message);
    // After a disconnect: retries reconnect() until it works (true) or the session stops (false).
    bool waitForReconnect();
    std::optional<frame::FramePtr> noteAge(std::optional<frame::FramePtr> frame);
    void push(SessionEvent event);
    void record(FrameRecord record);

    std::unique_ptr<Device> device_;
    std::string description_;
    Capabilities capabilities_;
    base::LatestSlot<frame::FramePtr> frames_;
    base::Worker capture_;
    std::atomic<bool> stopRequested_{false};
    std::atomic<DeviceState> state_{DeviceState::Closed};
    std::atomic<double> deviceFps_{0.0};
    base::RateMeter deliveries_; // capture thread only; published through deviceFps_
    mutable base::Mutex agesMutex_;
    base::RollingStats ages_ DC_GUARDED_BY(agesMutex_){
        31}; // ages of the frames consumers took, for latencyMs
    base::Mutex tapMutex_;
    std::function<void(const frame::FramePtr&)> tap_ DC_GUARDED_BY(tapMutex_);
    std::function<void()> listener_ DC_GUARDED_BY(tapMutex_);
    mutable base::Mutex eventsMutex_;
    std::vector<SessionEvent> events_ DC_GUARDED_BY(eventsMutex_);
    mutable base::Mutex recordsMutex_;
    std::deque<FrameRecord> records_ DC_GUARDED_BY(recordsMutex_);
    std::uint64_t recordsLost_ DC_GUARDED_BY(recordsMutex_) = 0;
};

} // namespace dc::devices
