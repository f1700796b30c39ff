#pragma once

#include "base/mutex.h"
#include "base/unique_fd.h"
#include "base/worker.h"
#include "devices/uvc/live_devices.h"
#include "devices/uvc/udev_monitor.h"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>

namespace dc::devices {

// Keeps a device picker's list of live cameras current. It lists once at start, then again shortly after
// udev reports a video4linux or usb device event (a burst of them, as a camera's interfaces bind and its
// nodes appear, gives one listing). Only when udev's monitor cannot be opened does it re-list every
// `fallbackPollInterval` instead. Listing opens device nodes, so it runs on the watcher's own thread, never
// on the UI's.
class LiveDeviceWatcher {
public:
    using Lister = std::function<LiveDeviceListing()>;
    using EventSourceFactory = std::function<Expected<std::unique_ptr<DeviceEventSource>>()>;

    // `lister` and `events` are the seams tests replace; by default the real USB + V4L2 listing and
    // udev's monitor.
    explicit LiveDeviceWatcher(
        std::chrono::milliseconds fallbackPollInterval = std::chrono::seconds(3),
        Lister lister = [] { return listLiveDevices(); }, const EventSourceFactory& events = openUdevMonitor);
    ~LiveDeviceWatcher();
    LiveDeviceWatcher(const LiveDeviceWatcher&) = delete;
    LiveDeviceWatcher& operator=(const LiveDeviceWatcher&) = delete;

    // The newest listing, if it differs from the last one returned (or none was returned yet).
    std::optional<LiveDeviceListing> takeUpdate();
    // True when device events drive the listing; false when it falls back to polling. Fixed at
    // construction.
    bool watchingEvents() const { return watchingEvents_; }

private:
    void run();
    void relist();

    std::chrono::milliseconds pollInterval_;
    Lister lister_;
    std::unique_ptr<DeviceEventSource> events_; // null: polling (watcher thread only once started)
    bool watchingEvents_ = false;
    base::UniqueFd stopFd_; // an eventfd: readable once the watcher is stopping
    std::atomic<bool> stopping_{false};
    base::Mutex mutex_;
    std::optional<LiveDeviceListing> pending_ DC_GUARDED_BY(mutex_);
    bool published_ DC_GUARDED_BY(mutex_) = false;
    std::string
        lastSignature_ DC_GUARDED_BY(mutex_); // of the last listing published, to publish changes only
    base::Worker thread_;
};

} // namespace dc::devices
