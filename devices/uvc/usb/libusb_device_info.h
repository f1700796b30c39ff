#pragma once

#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/usb/usb_device_info.h"

#include <libusb.h>

namespace dc::devices::usb {

// What one libusb device is. `openForStrings`: read the string descriptors through the device (not from a
// hotplug callback, where libusb forbids I/O; sysfs provides them there).
UsbDeviceInfo describeUsbDevice(libusb_device* device, const Sysfs& sysfs, bool openForStrings);

} // namespace dc::devices::usb
