#include "devices/uvc/udev_monitor.h"

#include <libudev.h>

#include <cstring>
#include <unistd.h>

namespace dc::devices {

namespace {

struct UdevDeleter {
    void operator()(udev* u) const { udev_unref(u); }
    void operator()(udev_monitor* m) const { udev_monitor_unref(m); }
    void operator()(udev_device* d) const { udev_device_unref(d); }
};
template <class T> using UdevPtr = std::unique_ptr<T, UdevDeleter>;

// udevd announces itself by this socket (libudev's own test for a running udevd).
constexpr const char* kUdevdControl = "/run/udev/control";

class UdevMonitor final : public DeviceEventSource {
public:
    UdevMonitor(UdevPtr<udev> context, UdevPtr<udev_monitor> monitor, std::string source)
        : context_(std::move(context)), monitor_(std::move(monitor)), source_(std::move(source)) {}

    int fd() const override { return udev_monitor_get_fd(monitor_.get()); }

    bool drain() override {
        bool relevant = false;
        // The socket is non-blocking: receive returns null once nothing is pending.
        while (UdevPtr<udev_device> device{udev_monitor_receive_device(monitor_.get())}) {
            const char* action = udev_device_get_action(device.get());
            // add/remove/bind/unbind change what is listed; "change" events (a format set on a loopback
            // node, a USB device's power state) may too, so every event of these subsystems counts.
            relevant = relevant || action != nullptr;
        }
        return relevant;
    }

    std::string name() const override { return "udev monitor (" + source_ + " events)"; }

private:
    UdevPtr<udev> context_;
    UdevPtr<udev_monitor> monitor_;
    std::string source_;
};

} // namespace

Expected<std::unique_ptr<DeviceEventSource>> openUdevMonitor() {
    UdevPtr<udev> context{udev_new()};
    if (!context)
        return Error{std::string("cannot create a udev context: ") + std::strerror(errno)};
    const char* source = ::access(kUdevdControl, F_OK) == 0 ? "udev" : "kernel";
    UdevPtr<udev_monitor> monitor{udev_monitor_new_from_netlink(context.get(), source)};
    if (!monitor)
        return Error{std::string("cannot open udev's ") + source + " monitor: " + std::strerror(errno)};
    if (udev_monitor_filter_add_match_subsystem_devtype(monitor.get(), "video4linux", nullptr) < 0 ||
        udev_monitor_filter_add_match_subsystem_devtype(monitor.get(), "usb", "usb_device") < 0)
        return Error{"cannot filter udev's monitor for video4linux and usb events"};
    if (const int r = udev_monitor_enable_receiving(monitor.get()); r < 0)
        return Error{std::string("cannot receive udev events: ") + std::strerror(-r)};
    return std::unique_ptr<DeviceEventSource>(
        std::make_unique<UdevMonitor>(std::move(context), std::move(monitor), source));
}

} // namespace dc::devices
