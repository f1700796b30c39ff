#pragma once

#include "base/expected.h"

#include <memory>
#include <string>

namespace dc::devices {

// Something that says, through a file descriptor poll() can wait on, that devices may have come or gone.
// udev's monitor in use (UdevMonitor); tests put a pipe behind it.
class DeviceEventSource {
public:
    virtual ~DeviceEventSource() = default;
    // Readable while events are pending.
    virtual int fd() const = 0;
    // Reads every pending event; true when any of them may change the list of cameras.
    virtual bool drain() = 0;
    // For the log: where the events come from.
    virtual std::string name() const = 0;
};

// udev's monitor of `video4linux` and `usb` device events, the ones that add or remove cameras (USB or
// not: vivid, v4l2loopback, platform ToF sensors). It listens to udevd's own events (sent once its rules
// have run, so a node's permissions are already set) when udevd runs, else to the kernel's, which need
// no daemon. An error when neither can be opened (no netlink socket: a sandbox); the caller then polls.
Expected<std::unique_ptr<DeviceEventSource>> openUdevMonitor();

} // namespace dc::devices
