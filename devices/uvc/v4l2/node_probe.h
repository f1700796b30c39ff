#pragma once

#include "base/expected.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "devices/uvc/v4l2/syscalls.h"
#include "devices/uvc/v4l2/v4l2_node.h"

#include <optional>
#include <string>
#include <vector>

namespace dc::devices::v4l2 {

// What a capture node offers, found by opening it briefly.
struct ProbedNode {
    std::string path;
    V4l2Capability capability;
    std::vector<V4l2Mode> modes;

    bool offers(std::uint32_t fourcc) const;
    bool offersRole(FormatRole role) const;
};

// Opens `path` and lists its modes. nullopt (with `error` set, -errno) when it cannot be opened; nullopt with
// error 0 for nodes that cannot capture video (UVC metadata nodes, gadget/output nodes).
std::optional<ProbedNode> probeNode(Syscalls& sys, const std::string& path, int& error);

// Which node of one camera is depth, color and infrared. Depth: the first node offering 'Z16 ', else the
// first offering 'Y16 ' (RealSense infrared nodes also list Y16, for calibration, next to a Z16 depth node).
// Color: the first other node with YUYV/NV12/MJPEG/RGB24. Infrared: the first remaining node with GREY or
// Y16.
struct NodeRoles {
    std::string depth;
    std::string color;
    std::string infrared;
};
NodeRoles assignRoles(const std::vector<ProbedNode>& nodes);
FormatRole roleOfNode(const NodeRoles& roles, const ProbedNode& node);

// The preferred color format among what a node offers: YUYV, NV12, RGB24, MJPEG (needs decoding), GREY.
std::optional<std::uint32_t> preferredImageFormat(const ProbedNode& node);

// A stream's mode: format, size and rate (0 = whatever the driver runs at).
struct ChosenMode {
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    double fps = 0.0;
};

// Picks a mode of `fourcc` from `modes`. A requested size (width/height > 0) must be offered; without one the
// largest size up to 1280x720 wins (the smallest offered if all are larger). A requested rate picks the
// nearest offered one; without one 30 fps when offered, else the highest. Errors list what is offered.
Expected<ChosenMode> chooseMode(const std::vector<V4l2Mode>& modes, const ChosenMode& request);

} // namespace dc::devices::v4l2
