#ifdef DC_HAVE_ROS
#include "devices/ros/ros_listing.h"
#endif
#include "devices/uvc/live_devices.h"
#include "devices/uvc/usb/hotplug_monitor.h"
#include "tool/live_commands.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>

namespace dc::tool {

namespace {

std::string rates(const std::vector<double>& fps) {
    std::string text;
    for (double r : fps) {
        char one[16];
        std::snprintf(one, sizeof one, "%g", r);
        text += (text.empty() ? "@" : "/") + std::string(one);
    }
    return text;
}

void printDevice(const devices::LiveDeviceInfo& d) {
    std::printf("%s\n", d.label().c_str());
    if (d.usb)
        std::printf(
            "  usb %s  manufacturer \"%s\"  product \"%s\"  serial \"%s\"  bus %d port %s address %d\n",
            d.usb->id().c_str(), d.usb->manufacturer.c_str(), d.usb->product.c_str(), d.usb->serial.c_str(),
            d.usb->bus, d.usb->portPath().c_str(), d.usb->address);
    if (!d.knownModel.empty())
        std::printf("  known model: %s, %g m per depth unit\n", d.knownModel.c_str(), d.depthScaleMeters);
    for (const devices::VideoNodeInfo& node : d.nodes) {
        std::printf("  %-8s %s  %s (%s)\n", devices::v4l2::toString(node.role), node.path.c_str(),
                    node.card.c_str(), node.driver.c_str());
        for (const devices::NodeMode& m : node.modes)
            std::printf("           '%s' %dx%d%s\n", m.fourcc.c_str(), m.width, m.height,
                        rates(m.framesPerSecond).c_str());
    }
    std::printf("  depth %s  color %s  infrared %s\n", d.depthNode.empty() ? "-" : d.depthNode.c_str(),
                d.colorNode.empty() ? "-" : d.colorNode.c_str(),
                d.infraredNode.empty() ? "-" : d.infraredNode.c_str());
    std::printf("  open with: depthcloud --source %s\n", d.sourceSpec.c_str());
}

nlohmann::json toJson(const devices::LiveDeviceInfo& d) {
    nlohmann::json nodes = nlohmann::json::array();
    for (const devices::VideoNodeInfo& node : d.nodes) {
        nlohmann::json modes = nlohmann::json::array();
        for (const devices::NodeMode& m : node.modes)
            modes.push_back(
                {{"fourcc", m.fourcc}, {"width", m.width}, {"height", m.height}, {"fps", m.framesPerSecond}});
        nodes.push_back({{"path", node.path},
                         {"driver", node.driver},
                         {"card", node.card},
                         {"busInfo", node.busInfo},
                         {"role", devices::v4l2::toString(node.role)},
                         {"modes", modes}});
    }
    nlohmann::json j{{"label", d.label()},
                     {"knownModel", d.knownModel},
                     {"depthScaleMeters", d.depthScaleMeters},
                     {"depthNode", d.depthNode},
                     {"colorNode", d.colorNode},
                     {"infraredNode", d.infraredNode},
                     {"source", d.sourceSpec},
                     {"nodes", nodes}};
    if (d.usb)
        j["usb"] = {{"id", d.usb->id()},         {"manufacturer", d.usb->manufacturer},
                    {"product", d.usb->product}, {"serial", d.usb->serial},
                    {"bus", d.usb->bus},         {"port", d.usb->portPath()},
                    {"address", d.usb->address}};
    return j;
}

int watchHotplug(double seconds) {
    devices::usb::HotplugMonitor monitor;
    if (Status s = monitor.start(); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    std::printf("watching USB hotplug for %g s\n", seconds);
    std::fflush(stdout);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        for (const auto& e : monitor.waitForEvents(std::chrono::milliseconds(100))) {
            std::printf("hotplug %s %s \"%s\" bus %d port %s\n", devices::usb::toString(e.kind),
                        e.device.id().c_str(), e.device.product.c_str(), e.device.bus,
                        e.device.portPath().c_str());
            std::fflush(stdout);
        }
    }
    return kExitOk;
}

#ifdef DC_HAVE_ROS
void printRos(const devices::ros::RosListing& ros) {
    if (!ros.problem.empty()) {
        std::printf("note: %s\n", ros.problem.c_str());
        return;
    }
    std::printf("ROS master %s: %zu image topic(s)\n", ros.masterUri.c_str(), ros.imageTopics.size());
    for (const std::string& topic : ros.imageTopics)
        std::printf("  %s  open with: depthcloud --source ros:%s\n", topic.c_str(), topic.c_str());
}

nlohmann::json toJson(const devices::ros::RosListing& ros) {
    return {{"master", ros.masterUri}, {"imageTopics", ros.imageTopics}, {"problem", ros.problem}};
}

void printRos2(const devices::ros::Ros2Listing& ros2) {
    if (!ros2.problem.empty()) {
        std::printf("note: %s\n", ros2.problem.c_str());
        return;
    }
    std::printf("ROS 2 domain %d: %zu image topic(s)\n", ros2.domain, ros2.imageTopics.size());
    for (const std::string& topic : ros2.imageTopics)
        std::printf("  %s  open with: depthcloud --source ros2:%s\n", topic.c_str(), topic.c_str());
}

nlohmann::json toJson(const devices::ros::Ros2Listing& ros2) {
    return {{"domain", ros2.domain}, {"imageTopics", ros2.imageTopics}, {"problem", ros2.problem}};
}
#endif

} // namespace

CLI::App* addDevicesCommand(CLI::App& app, DevicesOptions& o) {
    CLI::App* cmd = app.add_subcommand("devices", "list depth cameras: USB identity, V4L2 nodes, modes; with "
                                                  "ROS_MASTER_URI set, the master's image topics; with "
                                                  "ROS_DOMAIN_ID set, the ROS 2 domain's");
    cmd->add_flag("--all", o.all, "also list USB devices without a depth node");
    cmd->add_flag("--json", o.json, "print the listing as JSON");
    cmd->add_option("--watch", o.watchSeconds, "then print USB plug/unplug events for this many seconds")
        ->check(CLI::Range(0.0, 86400.0));
    return cmd;
}

int runDevices(const DevicesOptions& o) {
    devices::ListOptions options;
    options.includeNonDepth = o.all;
    const devices::LiveDeviceListing listing = devices::listLiveDevices(options);
#ifdef DC_HAVE_ROS
    // Only a master the environment names is asked: a desktop without ROS sees nothing of it.
    const devices::ros::RosListing ros = devices::ros::listRosImageTopics();
    const devices::ros::Ros2Listing ros2 = devices::ros::listRos2ImageTopics();
#endif
    if (o.json) {
        nlohmann::json devicesJson = nlohmann::json::array();
        for (const auto& d : listing.devices)
            devicesJson.push_back(toJson(d));
        nlohmann::json out{{"devices", devicesJson}, {"problems", listing.problems}};
#ifdef DC_HAVE_ROS
        if (ros.configured)
            out["ros"] = toJson(ros);
        if (ros2.configured)
            out["ros2"] = toJson(ros2);
#endif
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        if (listing.devices.empty())
            std::printf("no depth cameras found\n");
        for (const auto& d : listing.devices)
            printDevice(d);
        for (const std::string& p : listing.problems)
            std::printf("note: %s\n", p.c_str());
#ifdef DC_HAVE_ROS
        if (ros.configured)
            printRos(ros);
        if (ros2.configured)
            printRos2(ros2);
#endif
    }
    std::fflush(stdout);
    return o.watchSeconds > 0 ? watchHotplug(o.watchSeconds) : kExitOk;
}

} // namespace dc::tool
