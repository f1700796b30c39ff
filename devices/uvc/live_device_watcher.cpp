#include "devices/uvc/live_device_watcher.h"

#include "base/log.h"
#include "devices/uvc/usb/hotplug_monitor.h"

namespace dc::devices {

namespace {

// What the picker shows of a listing: a change in any of it is worth an update.
std::string signatureOf(const LiveDeviceListing& listing) {
    std::string s;
    for (const LiveDeviceInfo& d : listing.devices)
        s += d.sourceSpec + '\t' + d.label() + '\t' + d.depthNode + '\t' + d.colorNode + '\n';
    return s;
}

} // namespace

LiveDeviceWatcher::LiveDeviceWatcher(std::chrono::milliseconds pollInterval, Lister lister)
    : pollInterval_(pollInterval), lister_(std::move(lister)), thread_([this] { run(); }) {}

LiveDeviceWatcher::~LiveDeviceWatcher() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

std::optional<LiveDeviceListing> LiveDeviceWatcher::takeUpdate() {
    std::lock_guard lock(mutex_);
    return std::exchange(pending_, std::nullopt);
}

void LiveDeviceWatcher::relist() {
    LiveDeviceListing listing = lister_();
    std::string signature = signatureOf(listing);
    std::lock_guard lock(mutex_);
    if (published_ && signature == lastSignature_)
        return;
    published_ = true;
    lastSignature_ = std::move(signature);
    pending_ = std::move(listing);
}

bool LiveDeviceWatcher::sleepFor(std::chrono::milliseconds duration) {
    std::unique_lock lock(mutex_);
    return !wake_.wait_for(lock, duration, [this] { return stopping_; });
}

void LiveDeviceWatcher::run() {
    using namespace std::chrono_literals;
    usb::HotplugMonitor monitor;
    if (Status s = monitor.start(); !s)
        logInfo("camera list: no USB hotplug (" + s.error().message + "); re-listing every " +
                std::to_string(pollInterval_.count()) + " ms");
    // Short slices, so that the destructor never waits long for this thread.
    constexpr auto kSlice = 100ms;
    relist();
    auto sinceList = 0ms;
    while (sleepFor(monitor.running() ? 0ms : kSlice)) {
        bool plugged = false;
        if (monitor.running())
            plugged = !monitor.waitForEvents(kSlice).empty();
        sinceList += kSlice;
        if (plugged) {
            if (!sleepFor(500ms))
                return;
            relist();
            if (!sleepFor(1500ms))
                return;
            relist();
            sinceList = 0ms;
        } else if (sinceList >= pollInterval_) {
            relist();
            sinceList = 0ms;
        }
    }
}

} // namespace dc::devices
