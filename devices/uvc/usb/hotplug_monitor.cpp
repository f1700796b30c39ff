#include "devices/uvc/usb/hotplug_monitor.h"

#include "base/log.h"
#include "base/worker.h"
#include "devices/uvc/usb/libusb_device_info.h"
#include "devices/uvc/usb/libusb_handles.h"

#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

namespace dc::devices::usb {

namespace {
// How often the event thread re-checks its stop flag if libusb_interrupt_event_handler did not wake it.
constexpr timeval kEventTimeout{0, 200'000};
} // namespace

struct HotplugMonitor::Impl {
    UsbContext context;
    libusb_hotplug_callback_handle callback = 0;
    bool registered = false;
    base::Worker thread;
    std::atomic<bool> stopRequested{false};
    Sysfs sysfs;
    std::map<std::pair<int, int>, UsbDeviceInfo> known; // (bus, address); event thread only once started

    std::mutex mutex;
    std::condition_variable ready;
    std::vector<HotplugEvent> events;

    static int LIBUSB_CALL onEvent(libusb_context*, libusb_device* device, libusb_hotplug_event event,
                                   void* user) {
        static_cast<Impl*>(user)->handle(device, event);
        return 0; // stay registered
    }

    void handle(libusb_device* device, libusb_hotplug_event event) {
        const std::pair<int, int> key{libusb_get_bus_number(device), libusb_get_device_address(device)};
        HotplugEvent e;
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED) {
            e = {HotplugEvent::Kind::Arrived, describeUsbDevice(device, sysfs, false)};
            known[key] = e.device;
        } else {
            const auto it = known.find(key);
            e = {HotplugEvent::Kind::Left,
                 it != known.end() ? it->second : describeUsbDevice(device, sysfs, false)};
            if (it != known.end())
                known.erase(it);
        }
        std::lock_guard lock(mutex);
        events.push_back(std::move(e));
        ready.notify_all();
    }

    void run() {
        while (!stopRequested) {
            timeval timeout = kEventTimeout;
            libusb_handle_events_timeout_completed(context.get(), &timeout, nullptr);
        }
    }

    void rememberPresentDevices() {
        const UsbDeviceList list(context);
        for (libusb_device* device : list.devices())
            known[{libusb_get_bus_number(device), libusb_get_device_address(device)}] =
                describeUsbDevice(device, sysfs, false);
    }
};

const char* toString(HotplugEvent::Kind kind) {
    return kind == HotplugEvent::Kind::Arrived ? "arrived" : "left";
}

HotplugMonitor::HotplugMonitor() : impl_(std::make_unique<Impl>()) {}

HotplugMonitor::~HotplugMonitor() {
    stop();
}

bool HotplugMonitor::supported() {
    return libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0;
}

Status HotplugMonitor::start() {
    if (running())
        return {};
    if (!supported())
        return Error{"this libusb cannot report USB hotplug"};
    auto context = UsbContext::create();
    if (!context)
        return context.error();
    impl_->context = std::move(*context);
    impl_->rememberPresentDevices();
    const int r = libusb_hotplug_register_callback(
        impl_->context.get(),
        static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        static_cast<libusb_hotplug_flag>(0), LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
        LIBUSB_HOTPLUG_MATCH_ANY, &Impl::onEvent, impl_.get(), &impl_->callback);
    if (r != LIBUSB_SUCCESS) {
        impl_->context.reset();
        return Error{std::string("cannot register a USB hotplug callback: ") + libusb_error_name(r)};
    }
    impl_->registered = true;
    impl_->stopRequested = false;
    impl_->thread = base::Worker("the USB hotplug monitor stopped", [impl = impl_.get()] { impl->run(); });
    return {};
}

void HotplugMonitor::stop() {
    if (!impl_->thread.joinable())
        return;
    impl_->stopRequested = true;
    libusb_interrupt_event_handler(impl_->context.get());
    impl_->thread.join();
    if (impl_->registered)
        libusb_hotplug_deregister_callback(impl_->context.get(), impl_->callback);
    impl_->registered = false;
    impl_->context.reset();
    impl_->known.clear();
}

bool HotplugMonitor::running() const {
    return impl_->thread.joinable();
}

std::vector<HotplugEvent> HotplugMonitor::drain() {
    std::lock_guard lock(impl_->mutex);
    return std::exchange(impl_->events, {});
}

std::vector<HotplugEvent> HotplugMonitor::waitForEvents(std::chrono::milliseconds timeout) {
    std::unique_lock lock(impl_->mutex);
    impl_->ready.wait_for(lock, timeout, [this] { return !impl_->events.empty(); });
    return std::exchange(impl_->events, {});
}

} // namespace dc::devices::usb
