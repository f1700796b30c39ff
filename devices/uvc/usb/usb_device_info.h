#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices::usb {

// VID:PID with an optional serial number: how a live source names its camera ("8086:0b07[:SERIAL]").
struct UsbMatch {
    std::uint16_t vendorId = 0;
    std::uint16_t productId = 0;
    std::string serial; // empty: any serial

    // Parses "VID:PID" or "VID:PID:SERIAL" (hex ids, 1-4 digits each).
    static std::optional<UsbMatch> parse(const std::string& text);
    std::string toString() const;
};

// One USB device as enumeration saw it. Plain data, so the UI can hold it without including libusb.
struct UsbDeviceInfo {
    std::uint16_t vendorId = 0;
    std::uint16_t productId = 0;
    std::string manufacturer; // string descriptors; empty when the device has none or cannot be read
    std::string product;
    std::string serial;
    int bus = 0;
    int address = 0;
    std::vector<int> ports;         // port numbers from the root hub down
    bool hasVideoInterface = false; // a USB Video Class interface (class 0x0e)

    std::string id() const; // "8086:0b07"
    // The kernel's name for the device: "<bus>-<port>[.<port>...]" (/sys/bus/usb/devices/1-1.2).
    std::string sysfsName() const;
    std::string portPath() const; // "1.2"
    bool matches(const UsbMatch& match) const;
};

std::string hexId(std::uint16_t vendorId, std::uint16_t productId);

} // namespace dc::devices::usb
