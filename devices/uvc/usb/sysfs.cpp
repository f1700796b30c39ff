#include "devices/uvc/usb/sysfs.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>

namespace dc::devices::usb {

namespace fs = std::filesystem;

namespace {

std::string readAttribute(const fs::path& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' '))
        line.pop_back();
    return line;
}

template <class T> bool parseNumber(const std::string& text, T& out, int base = 10) {
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out, base);
    return !text.empty() && ec == std::errc() && ptr == end;
}

// "videoN" -> N, or -1 for any other name.
int videoIndex(const std::string& name) {
    int n = -1;
    if (name.rfind("video", 0) != 0 || !parseNumber(name.substr(5), n))
        return -1;
    return n;
}

std::vector<std::string> sortedNodes(std::vector<int> indices) {
    std::sort(indices.begin(), indices.end());
    indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
    std::vector<std::string> nodes;
    for (int n : indices)
        nodes.push_back("/dev/video" + std::to_string(n));
    return nodes;
}

// "1-1.2" -> bus 1, ports {1, 2}; false for root hubs ("usb1") and interfaces ("1-1:1.0").
bool parseUsbName(const std::string& name, int& bus, std::vector<int>& ports) {
    const auto dash = name.find('-');
    if (dash == std::string::npos || name.find(':') != std::string::npos ||
        !parseNumber(name.substr(0, dash), bus))
        return false;
    ports.clear();
    std::size_t start = dash + 1;
    while (start <= name.size()) {
        const auto dot = std::min(name.find('.', start), name.size());
        int port = 0;
        if (!parseNumber(name.substr(start, dot - start), port))
            return false;
        ports.push_back(port);
        start = dot + 1;
    }
    return !ports.empty();
}

} // namespace

std::vector<std::string> Sysfs::videoNodesOf(const std::string& usbSysfsName) const {
    std::vector<int> indices;
    std::error_code ec;
    const fs::path device = fs::path(root_) / "bus/usb/devices" / usbSysfsName;
    for (const auto& entry : fs::directory_iterator(device, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(usbSysfsName + ":", 0) != 0) // only this device's interfaces
            continue;
        std::error_code inner;
        for (const auto& node : fs::directory_iterator(entry.path() / "video4linux", inner))
            if (const int n = videoIndex(node.path().filename().string()); n >= 0)
                indices.push_back(n);
    }
    return sortedNodes(std::move(indices));
}

std::vector<std::string> Sysfs::allVideoNodes() const {
    std::vector<int> indices;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(root_) / "class/video4linux", ec))
        if (const int n = videoIndex(entry.path().filename().string()); n >= 0)
            indices.push_back(n);
    return sortedNodes(std::move(indices));
}

std::optional<UsbDeviceInfo> Sysfs::usbDeviceOf(const std::string& nodePath) const {
    const std::string name = fs::path(nodePath).filename().string();
    if (videoIndex(name) < 0)
        return std::nullopt;
    std::error_code ec;
    // .../1-1.2/1-1.2:1.0/video4linux/videoN: the node's "device" is the interface; its parent the device.
    const fs::path interface = fs::canonical(fs::path(root_) / "class/video4linux" / name / "device", ec);
    if (ec)
        return std::nullopt;
    return usbDevice(interface.parent_path().filename().string());
}

std::string Sysfs::busOf(const std::string& nodePath) const {
    std::error_code ec;
    const fs::path subsystem = fs::read_symlink(
        fs::path(root_) / "class/video4linux" / fs::path(nodePath).filename() / "device/subsystem", ec);
    return ec ? std::string() : subsystem.filename().string();
}

std::optional<UsbDeviceInfo> Sysfs::usbDevice(const std::string& usbSysfsName) const {
    UsbDeviceInfo info;
    if (!parseUsbName(usbSysfsName, info.bus, info.ports))
        return std::nullopt;
    const fs::path dir = fs::path(root_) / "bus/usb/devices" / usbSysfsName;
    if (!parseNumber(readAttribute(dir / "idVendor"), info.vendorId, 16) ||
        !parseNumber(readAttribute(dir / "idProduct"), info.productId, 16))
        return std::nullopt;
    parseNumber(readAttribute(dir / "devnum"), info.address);
    info.manufacturer = readAttribute(dir / "manufacturer");
    info.product = readAttribute(dir / "product");
    info.serial = readAttribute(dir / "serial");
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(usbSysfsName + ":", 0) == 0 && readAttribute(entry.path() / "bInterfaceClass") == "0e")
            info.hasVideoInterface = true;
    }
    return info;
}

std::vector<UsbDeviceInfo> Sysfs::usbDevices() const {
    std::vector<UsbDeviceInfo> result;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(root_) / "bus/usb/devices", ec))
        if (auto info = usbDevice(entry.path().filename().string()))
            result.push_back(std::move(*info));
    std::sort(result.begin(), result.end(),
              [](const UsbDeviceInfo& a, const UsbDeviceInfo& b) { return a.sysfsName() < b.sysfsName(); });
    return result;
}

} // namespace dc::devices::usb
