#pragma once

#include "base/expected.h"
#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/usb/usb_device_info.h"

#include <vector>

namespace dc::devices::usb {

// Every USB device libusb sees (root hubs excluded): ids, bus, address, port path, whether it has a video
// interface, and its strings. Strings are read from the device through libusb when the user may open it,
// else from sysfs, which anyone may read, so an unprivileged listing still names the camera.
Expected<std::vector<UsbDeviceInfo>> enumerateUsbDevices(const Sysfs& sysfs = Sysfs());

} // namespace dc::devices::usb
