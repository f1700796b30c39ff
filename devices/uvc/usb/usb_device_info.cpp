#include "devices/uvc/usb/usb_device_info.h"

#include <charconv>
#include <cstdio>

namespace dc::devices::usb {

namespace {

bool parseHex16(const std::string& text, std::uint16_t& out) {
    if (text.empty() || text.size() > 4)
        return false;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out, 16);
    return ec == std::errc() && ptr == end;
}

} // namespace

std::optional<UsbMatch> UsbMatch::parse(const std::string& text) {
    const auto first = text.find(':');
    if (first == std::string::npos)
        return std::nullopt;
    const auto second = text.find(':', first + 1);
    UsbMatch match;
    if (!parseHex16(text.substr(0, first), match.vendorId) ||
        !parseHex16(
            text.substr(first + 1, second == std::string::npos ? std::string::npos : second - first - 1),
            match.productId))
        return std::nullopt;
    if (second != std::string::npos) {
        match.serial = text.substr(second + 1);
        if (match.serial.empty())
            return std::nullopt;
    }
    return match;
}

std::string UsbMatch::toString() const {
    return hexId(vendorId, productId) + (serial.empty() ? "" : ":" + serial);
}

std::string hexId(std::uint16_t vendorId, std::uint16_t productId) {
    char text[10];
    std::snprintf(text, sizeof text, "%04x:%04x", vendorId, productId);
    return text;
}

std::string UsbDeviceInfo::id() const {
    return hexId(vendorId, productId);
}

std::string UsbDeviceInfo::portPath() const {
    std::string path;
    for (int port : ports)
        path += (path.empty() ? "" : ".") + std::to_string(port);
    return path;
}

std::string UsbDeviceInfo::sysfsName() const {
    return ports.empty() ? "usb" + std::to_string(bus) : std::to_string(bus) + "-" + portPath();
}

bool UsbDeviceInfo::matches(const UsbMatch& match) const {
    return vendorId == match.vendorId && productId == match.productId &&
           (match.serial.empty() || serial == match.serial);
}

} // namespace dc::devices::usb
