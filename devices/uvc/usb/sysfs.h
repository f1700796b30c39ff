#pragma once

#include "devices/uvc/usb/usb_device_info.h"

#include <optional>
#include <string>
#include <vector>

namespace dc::devices::usb {

// The USB and V4L2 topology as sysfs shows it: which /dev/videoN nodes belong to which USB device. `root`
// is "/sys" except in tests, which build a fake tree in a temporary directory.
class Sysfs {
public:
    explicit Sysfs(std::string root = "/sys") : root_(std::move(root)) {}

    // The V4L2 nodes of a USB device's interfaces (/sys/bus/usb/devices/1-1.2/1-1.2:1.0/video4linux/video0),
    // as /dev paths in node-number order.
    std::vector<std::string> videoNodesOf(const std::string& usbSysfsName) const;
    // Every registered V4L2 node, in node-number order.
    std::vector<std::string> allVideoNodes() const;
    // The USB device a V4L2 node belongs to; nullopt for nodes of virtual drivers (vivid, v4l2loopback).
    std::optional<UsbDeviceInfo> usbDeviceOf(const std::string& nodePath) const;
    // The identity attributes of one USB device ("1-1.2"), or nullopt when it is not there.
    std::optional<UsbDeviceInfo> usbDevice(const std::string& usbSysfsName) const;
    // The bus of the device behind a V4L2 node ("usb", "platform", "gadget"...); empty if unknown. A "gadget"
    // node is the device side of a USB gadget: opening it connects the gadget, so listings leave it alone.
    std::string busOf(const std::string& nodePath) const;
    // Every USB device that is not a root hub.
    std::vector<UsbDeviceInfo> usbDevices() const;

private:
    std::string root_;
};

} // namespace dc::devices::usb
