#pragma once

#include "base/expected.h"
#include "devices/uvc/usb/usb_device_info.h"
#include "devices/uvc/v4l2/pixel_formats.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices {

// One size of one format of a V4L2 node, with the rates it offers.
struct NodeMode {
    std::string fourcc; // "Z16 ", "YUYV"...
    int width = 0;
    int height = 0;
    std::vector<double> framesPerSecond;
};

struct VideoNodeInfo {
    std::string path; // /dev/videoN
    std::string driver;
    std::string card;
    std::string busInfo;
    v4l2::FormatRole role = v4l2::FormatRole::Other; // what this node is best used for
    std::vector<NodeMode> modes;
};

// A camera as the device picker shows it: its USB identity (absent for virtual V4L2 drivers such as vivid
// or v4l2loopback), its capture nodes, which of them is depth, color and infrared, and the --source value
// that opens it. Plain data: the UI includes neither libusb nor V4L2 headers.
struct LiveDeviceInfo {
    std::optional<usb::UsbDeviceInfo> usb;
    std::string knownModel;           // from the known-camera table, empty if unknown
    float depthScaleMeters = 0.001f;  // meters per depth unit: the table's, or the default
    std::vector<VideoNodeInfo> nodes; // capture nodes only (metadata and output nodes are left out)
    std::string depthNode;            // empty when no node offers Z16/Y16
    std::string colorNode;
    std::string infraredNode;
    std::string sourceSpec; // "usb:8086:0b07:SERIAL" or "v4l2:/dev/video10"

    bool depthCapable() const { return !depthNode.empty(); }
    std::string label() const; // "Fake Depth Inc Virtual Z16 Depth Camera (8086:0b07)"
};

struct LiveDeviceListing {
    std::vector<LiveDeviceInfo> devices;
    std::vector<std::string> problems; // e.g. libusb unavailable, a node that could not be opened
};

struct ListOptions {
    bool includeNonDepth = false; // also USB devices without a depth node (e.g. plain webcams)
    std::string sysfsRoot = "/sys";
};

// Enumerates USB devices (libusb), maps each to its V4L2 nodes (sysfs), classifies the nodes by their formats
// (a node with Z16 is depth before one with only Y16; YUYV/NV12/MJPEG/RGB24 color; GREY infrared), and adds
// depth nodes that are not on USB. A device counts as a depth camera when it is in the known-camera table
// or has a Z16/Y16 node. Opening nodes to list them does not disturb a stream running on them.
LiveDeviceListing listLiveDevices(const ListOptions& options = {});

} // namespace dc::devices
