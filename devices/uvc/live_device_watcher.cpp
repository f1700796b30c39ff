#include "devices/uvc/live_device_watcher.h"

#include "base/log.h"
#include "base/worker.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

namespace dc::devices {

namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// After a device event, how long to wait for the rest of its burst (a USB camera's interfaces bind and
// its V4L2 nodes appear over a few hundred milliseconds) before listing once.
constexpr auto kSettle = 300ms;
// Without an eventfd to wake it, how often the thread looks whether it should stop.
constexpr int kStopCheckMs = 100;

// What the picker shows of a listing: a change in any of it is worth an update.
std::string signatureOf(const LiveDeviceListing& listing) {
    std::string s;
    for (const LiveDeviceInfo& d : listing.devices)
        s += d.sourceSpec + '\t' + d.label() + '\t' + d.depthNode + '\t' + d.colorNode + '\n';
    return s;
}

int millisecondsUntil(Clock::time_point due) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(due - Clock::now());
    return static_cast<int>(std::max<std::int64_t>(0, left.count()));
}

} // namespace

LiveDeviceWatcher::LiveDeviceWatcher(std::chrono::milliseconds fallbackPollInterval, Lister lister,
                                     const EventSourceFactory& events)
    : pollInterval_(fallbackPollInterval), lister_(std::move(lister)),
      stopFd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
    if (auto source = events ? events() : Expected<std::unique_ptr<DeviceEventSource>>(Error{"none"});
        source) {
        events_ = std::move(*source);
        watchingEvents_ = true;
    } else {
        logInfo("camera list: no device events (" + source.error().message + "); re-listing every " +
                std::to_string(pollInterval_.count()) + " ms");
    }
    thread_ = base::Worker("the camera watcher stopped", [this] { run(); });
}

LiveDeviceWatcher::~LiveDeviceWatcher() {
    stopping_ = true;
    const std::uint64_t one = 1;
    if (stopFd_.valid() && ::write(stopFd_.get(), &one, sizeof one) < 0)
        logError(std::string("camera list: cannot wake the watcher to stop: ") + std::strerror(errno));
    thread_.join();
}

std::optional<LiveDeviceListing> LiveDeviceWatcher::takeUpdate() {
    base::MutexLock lock(mutex_);
    return std::exchange(pending_, std::nullopt);
}

void LiveDeviceWatcher::relist() {
    LiveDeviceListing listing = lister_();
    std::string signature = signatureOf(listing);
    base::MutexLock lock(mutex_);
    if (published_ && signature == lastSignature_)
        return;
    published_ = true;
    lastSignature_ = std::move(signature);
    pending_ = std::move(listing);
}

void LiveDeviceWatcher::run() {
    relist();
    // With events: list once a burst has settled. Without: list every poll interval.
    // `kNever`: no listing is due (an event will say when).
    constexpr Clock::time_point kNever = Clock::time_point::max();
    Clock::time_point due = events_ ? kNever : Clock::now() + pollInterval_;
    while (!stopping_) {
        pollfd fds[2] = {{stopFd_.get(), POLLIN, 0}, {events_ ? events_->fd() : -1, POLLIN, 0}};
        int timeoutMs = due == kNever ? -1 : millisecondsUntil(due);
        if (!stopFd_.valid()) // nothing can wake the poll: look at stopping_ now and then
            timeoutMs = timeoutMs < 0 ? kStopCheckMs : std::min(timeoutMs, kStopCheckMs);
        if (::poll(fds, 2, timeoutMs) < 0 && errno != EINTR) {
            logError(std::string("camera list: poll failed, the list is no longer kept current: ") +
                     std::strerror(errno));
            return;
        }
        if (fds[0].revents != 0)
            return;
        if ((fds[1].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
            logWarning("camera list: " + events_->name() + " failed; re-listing every " +
                       std::to_string(pollInterval_.count()) + " ms instead");
            events_.reset();
            due = Clock::now();
        } else if (fds[1].revents != 0 && events_->drain()) {
            due = Clock::now() + kSettle;
        }
        if (due != kNever && Clock::now() >= due) {
            relist();
            due = events_ ? kNever : Clock::now() + pollInterval_;
        }
    }
}

} // namespace dc::devices
