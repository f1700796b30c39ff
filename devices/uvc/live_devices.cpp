#include "devices/uvc/live_devices.h"

#include "devices/uvc/usb/known_cameras.h"
#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/usb/usb_enumeration.h"
#include "devices/uvc/v4l2/node_probe.h"

#include <cstring>
#include <set>

namespace dc::devices {

namespace {

std::vector<v4l2::ProbedNode> probeAll(const std::vector<std::string>& paths,
                                       std::vector<std::string>& problems) {
    std::vector<v4l2::ProbedNode> probed;
    for (const std::string& path : paths) {
        int error = 0;
        if (auto node = v4l2::probeNode(v4l2::systemSyscalls(), path, error))
            probed.push_back(std::move(*node));
        else if (error < 0)
            problems.push_back("cannot open " + path + ": " + std::strerror(-error));
    }
    return probed;
}

void fillNodes(LiveDeviceInfo& info, const std::vector<v4l2::ProbedNode>& probed) {
    const v4l2::NodeRoles roles = v4l2::assignRoles(probed);
    info.depthNode = roles.depth;
    info.colorNode = roles.color;
    info.infraredNode = roles.infrared;
    for (const v4l2::ProbedNode& node : probed) {
        VideoNodeInfo out{node.path,
                          node.capability.driver,
                          node.capability.card,
                          node.capability.busInfo,
                          v4l2::roleOfNode(roles, node),
                          {}};
        for (const v4l2::V4l2Mode& m : node.modes)
            out.modes.push_back({v4l2::fourccToString(m.fourcc), m.width, m.height, m.framesPerSecond});
        info.nodes.push_back(std::move(out));
    }
}

std::optional<LiveDeviceInfo> describeUsbCamera(const usb::UsbDeviceInfo& device, const usb::Sysfs& sysfs,
                                                const ListOptions& options,
                                                std::vector<std::string>& problems) {
    LiveDeviceInfo info;
    info.usb = device;
    const usb::KnownCamera* known = usb::findKnownCamera(device.vendorId, device.productId);
    if (known) {
        info.knownModel = known->name;
        info.depthScaleMeters = known->depthScaleMeters;
    }
    fillNodes(info, probeAll(sysfs.videoNodesOf(device.sysfsName()), problems));
    if (!known && !info.depthCapable() && !options.includeNonDepth)
        return std::nullopt;
    info.sourceSpec = "usb:" + usb::UsbMatch{device.vendorId, device.productId, device.serial}.toString();
    return info;
}

} // namespace

std::string LiveDeviceInfo::label() const {
    std::string name;
    if (usb) {
        name = usb->manufacturer;
        if (!usb->product.empty())
            name += (name.empty() ? "" : " ") + usb->product;
        if (name.empty())
            name = knownModel.empty() ? "USB camera" : knownModel;
        return name + " (" + usb->id() + ")";
    }
    for (const VideoNodeInfo& node : nodes)
        if (node.path == depthNode)
            return node.card + " (" + node.path + ")";
    return depthNode;
}

LiveDeviceListing listLiveDevices(const ListOptions& options) {
    LiveDeviceListing listing;
    const usb::Sysfs sysfs(options.sysfsRoot);
    std::set<std::string> onUsb;
    if (auto devices = usb::enumerateUsbDevices(sysfs); devices) {
        for (const usb::UsbDeviceInfo& device : *devices) {
            for (const std::string& node : sysfs.videoNodesOf(device.sysfsName()))
                onUsb.insert(node);
            if (auto info = describeUsbCamera(device, sysfs, options, listing.problems))
                listing.devices.push_back(std::move(*info));
        }
    } else {
        listing.problems.push_back(devices.error().message);
    }
    // Depth nodes of drivers that are not on USB (vivid, v4l2loopback, platform ToF sensors): one entry each.
    for (const std::string& path : sysfs.allVideoNodes()) {
        if (onUsb.count(path) || sysfs.usbDeviceOf(path) || sysfs.busOf(path) == "gadget")
            continue;
        LiveDeviceInfo info;
        fillNodes(info, probeAll({path}, listing.problems));
        if (!info.depthCapable())
            continue;
        info.sourceSpec = "v4l2:" + path;
        listing.devices.push_back(std::move(info));
    }
    return listing;
}

} // namespace dc::devices
