#pragma once

#include "base/expected.h"
#include "devices/uvc/usb/usb_device_info.h"

#include <chrono>
#include <memory>
#include <vector>

namespace dc::devices::usb {

struct HotplugEvent {
    enum class Kind { Arrived, Left };
    Kind kind = Kind::Arrived;
    UsbDeviceInfo device; // for Left: what the device was when it arrived or when the monitor started
};

const char* toString(HotplugEvent::Kind kind);

// Watches USB plug and unplug with libusb hotplug callbacks on its own thread and queues the events as
// values; the UI drains them once per frame (and then re-lists devices: a camera's V4L2 nodes appear a
// moment after its USB arrival, when uvcvideo has bound). Nothing of libusb leaks out of this class.
// On Linux libusb learns of hotplug through udev, so a system without a running udevd reports no events.
class HotplugMonitor {
public:
    HotplugMonitor();
    ~HotplugMonitor();
    HotplugMonitor(const HotplugMonitor&) = delete;
    HotplugMonitor& operator=(const HotplugMonitor&) = delete;

    static bool supported();
    Status start();
    void stop();
    bool running() const;

    std::vector<HotplugEvent> drain();
    // Waits up to `timeout` for at least one event (tests, the CLI), then drains.
    std::vector<HotplugEvent> waitForEvents(std::chrono::milliseconds timeout);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace dc::devices::usb
