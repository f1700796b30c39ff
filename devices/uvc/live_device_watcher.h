#pragma once

#include "devices/uvc/live_devices.h"

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace dc::devices {

// Keeps a device picker's list of live cameras current. It lists once at start, again shortly after every
// libusb hotplug event (twice: uvcvideo creates the V4L2 nodes a moment after the USB arrival, and removes
// them a moment after the departure), and every `pollInterval` regardless, because hotplug needs a running
// udevd and never reports virtual V4L2 drivers (vivid, v4l2loopback). Listing opens device nodes, so it
// runs on the watcher's own thread, never on the UI's.
class LiveDeviceWatcher {
public:
    using Lister = std::function<LiveDeviceListing()>;

    // `lister` is the seam tests replace; by default the real USB + V4L2 listing.
    explicit LiveDeviceWatcher(
        std::chrono::milliseconds pollInterval = std::chrono::seconds(3),
        Lister lister = [] { return listLiveDevices(); });
    ~LiveDeviceWatcher();
    LiveDeviceWatcher(const LiveDeviceWatcher&) = delete;
    LiveDeviceWatcher& operator=(const LiveDeviceWatcher&) = delete;

    // The newest listing, if it differs from the last one returned (or none was returned yet).
    std::optional<LiveDeviceListing> takeUpdate();

private:
    void run();
    void relist();
    // Sleeps up to `duration`; false when the watcher is stopping.
    bool sleepFor(std::chrono::milliseconds duration);

    std::chrono::milliseconds pollInterval_;
    Lister lister_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::optional<LiveDeviceListing> pending_;
    bool published_ = false;
    std::string lastSignature_; // of the last listing published, to publish changes only
    std::thread thread_;
};

} // namespace dc::devices
