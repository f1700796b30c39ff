#include "devices/uvc/live_source_spec.h"

#include "devices/source_pose.h"
#include "devices/uvc/live_devices.h"
#include "devices/uvc/v4l2/node_probe.h"
#include "devices/uvc/v4l2/pixel_formats.h"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <linux/videodev2.h>
#include <sstream>
#include <vector>

namespace dc::devices {

namespace {

std::vector<std::string> splitColons(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, ':');)
        parts.push_back(part);
    return parts;
}

template <class T> bool number(const std::string& text, T& out) {
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return !text.empty() && ec == std::errc() && ptr == end;
}

bool looksLikeMode(const std::string& part) {
    return !part.empty() && part.find('x') != std::string::npos &&
           std::isdigit(static_cast<unsigned char>(part[0]));
}

// WxH or WxH@FPS into `width`, `height` and (when given) `fps`; `what` names the part in the error.
Status parseMode(const std::string& part, const std::string& what, int& width, int& height, double& fps) {
    const auto at = part.find('@');
    const std::string size = part.substr(0, at);
    const auto x = size.find('x');
    if (x == std::string::npos || !number(size.substr(0, x), width) || !number(size.substr(x + 1), height) ||
        width <= 0 || height <= 0 ||
        (at != std::string::npos && (!number(part.substr(at + 1), fps) || !(fps > 0.0))))
        return Error{"malformed " + what + " '" + part +
                     "' in --source (expected WxH or WxH@FPS, e.g. 640x480@30)"};
    return {};
}

Status parseColorFormat(const std::string& value, UvcConfig& config) {
    const auto fourcc = v4l2::parseFourcc(value);
    const v4l2::FormatRole role = fourcc ? v4l2::roleOf(*fourcc) : v4l2::FormatRole::Other;
    if (role != v4l2::FormatRole::Color && role != v4l2::FormatRole::Guide)
        return Error{"colorformat=" + value +
                     " in --source: the colour format must be YUYV, NV12, RGB3, MJPG or GREY"};
    config.colorFourcc = fourcc;
    return {};
}

Status parseOption(const std::string& key, const std::string& value, UvcConfig& config) {
    if (key == "format") {
        const auto fourcc = v4l2::parseFourcc(value);
        if (!fourcc || (*fourcc != V4L2_PIX_FMT_Z16 && *fourcc != V4L2_PIX_FMT_Y16))
            return Error{"format=" + value + " in --source: the depth format must be Z16 or Y16"};
        config.depthFourcc = fourcc;
    } else if (key == "scale") {
        float scale = 0.0f;
        if (!number(value, scale) || !(scale > 0.0f))
            return Error{"scale=" + value + " in --source: expected meters per depth unit, e.g. scale=0.001"};
        config.depthScaleMeters = scale;
    } else if (key == "calib") {
        auto calibration = frame::loadCalibration(value);
        if (!calibration)
            return calibration.error();
        config.calibration = std::move(*calibration);
    } else if (key == "color") {
        config.color = value != "none";
        config.colorNode = config.color ? value : "";
    } else if (key == "colormode") {
        return parseMode(value, "colormode", config.colorWidth, config.colorHeight, config.colorFps);
    } else if (key == "colorformat") {
        return parseColorFormat(value, config);
    } else if (key == "watchdog") {
        int ms = 0;
        if (!number(value, ms) || ms <= 0)
            return Error{"watchdog=" + value + " in --source: expected milliseconds, e.g. watchdog=2000"};
        config.watchdog = std::chrono::milliseconds(ms);
    } else if (key == "preset") {
        auto preset = v4l2::readPreset(value);
        if (!preset)
            return Error{"preset=" + value + " in --source: " + preset.error().message};
        config.preset = std::move(*preset);
        config.presetPath = value;
    } else {
        return Error{"unknown option '" + key +
                     "' in --source (format, scale, calib, color, colormode, colorformat, watchdog, preset)"};
    }
    return {};
}

Status parseOptions(const std::vector<std::string>& parts, std::size_t first, UvcConfig& config) {
    for (std::size_t i = first; i < parts.size(); ++i) {
        const std::string& part = parts[i];
        const auto eq = part.find('=');
        Status s = eq != std::string::npos ? parseOption(part.substr(0, eq), part.substr(eq + 1), config)
                   : looksLikeMode(part)   ? parseMode(part, "mode", config.width, config.height, config.fps)
                                           : Status(Error{"unknown part '" + part + "' in --source"});
        if (!s)
            return s;
    }
    return {};
}

Status checkDepthNode(const std::string& path) {
    int error = 0;
    if (v4l2::probeNode(v4l2::systemSyscalls(), path, error))
        return {};
    // Only what no retry can change is the argument's fault; a busy or forbidden node is reported when
    // the device opens, like any failure while running.
    if (error == 0 || error == -ENOENT || error == -ENOTTY || error == -ENXIO || error == -ENODEV ||
        error == -ENOTDIR)
        return Error{"v4l2:" + path + ": not a video capture node" +
                     (error < 0 ? std::string(" (") + std::strerror(-error) + ")" : std::string())};
    return {};
}

} // namespace

Expected<std::vector<std::string>> cameraNodePaths(const UvcConfig& config) {
    if (!config.usb) {
        std::vector<std::string> nodes{config.depthNode};
        if (!config.colorNode.empty())
            nodes.push_back(config.colorNode);
        return nodes;
    }
    for (const LiveDeviceInfo& d : listLiveDevices().devices) {
        const bool same = d.usb && d.usb->vendorId == config.usb->vendorId &&
                          d.usb->productId == config.usb->productId &&
                          (config.usb->serial.empty() || d.usb->serial == config.usb->serial);
        if (!same)
            continue;
        std::vector<std::string> nodes;
        for (const VideoNodeInfo& node : d.nodes)
            nodes.push_back(node.path);
        return nodes;
    }
    return Error{"no camera matches usb:" + config.usb->toString()};
}

bool isLiveSourceSpec(const std::string& spec) {
    return spec.rfind("v4l2:", 0) == 0 || spec.rfind("usb:", 0) == 0;
}

// Where a spec's options start: after v4l2:PATH, or after usb:VID:PID and the serial if one is given.
std::size_t firstOption(const std::vector<std::string>& parts) {
    if (parts.empty() || parts[0] != "usb")
        return 2;
    const bool hasSerial =
        parts.size() >= 4 && parts[3].find('=') == std::string::npos && !looksLikeMode(parts[3]);
    return hasSerial ? 4 : 3;
}

namespace {

std::string modeText(const StreamMode& mode) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", mode.fps);
    return std::to_string(mode.width) + "x" + std::to_string(mode.height) + "@" + rate;
}

// `spec` with `added` (":OPTION...") right after the camera's name and every option that `replaced` says
// true of left out.
template <class Replaced>
std::string withOptions(const std::string& spec, const std::string& added, Replaced replaced) {
    const std::vector<std::string> parts = splitColons(spec);
    const std::size_t options = firstOption(parts);
    std::string out;
    for (std::size_t i = 0; i < options; ++i)
        out += (i ? ":" : "") + parts[i];
    out += added;
    for (std::size_t i = options; i < parts.size(); ++i)
        if (!replaced(parts[i]))
            out += ":" + parts[i];
    return out;
}

} // namespace

Expected<std::string> withDepthMode(const std::string& spec, const StreamMode& mode) {
    if (auto config = parseLiveSourceSpec(spec); !config)
        return config.error();
    return withOptions(spec, ":" + modeText(mode) + ":format=" + mode.format, [](const std::string& part) {
        return looksLikeMode(part) || part.starts_with("format=");
    });
}

Expected<std::string> withColorMode(const std::string& spec, const StreamMode& mode) {
    auto config = parseLiveSourceSpec(spec);
    if (!config)
        return config.error();
    if (!config->color)
        return Error{spec + " streams no colour (color=none): it has no colour mode to choose"};
    return withOptions(spec, ":colormode=" + modeText(mode) + ":colorformat=" + mode.format,
                       [](const std::string& part) {
                           return part.starts_with("colormode=") || part.starts_with("colorformat=");
                       });
}

Expected<UvcConfig> parseLiveSourceSpec(const std::string& given) {
    // pose= places the camera in the world, which is not the camera's business (`depthcloud controls` reads
    // a spec the viewer took, pose= and all).
    auto placement = sourcePlacement(given);
    if (!placement)
        return placement.error();
    const std::string& spec = placement->spec;
    const std::vector<std::string> parts = splitColons(spec);
    UvcConfig config;
    const std::size_t options = firstOption(parts);
    if (parts.size() >= 2 && parts[0] == "v4l2") {
        if (parts[1].empty())
            return Error{"v4l2: needs a node, e.g. --source v4l2:/dev/video0"};
        config.depthNode = parts[1];
    } else if (parts.size() >= 3 && parts[0] == "usb") {
        const std::string ids = parts[1] + ":" + parts[2] + (options == 4 ? ":" + parts[3] : "");
        config.usb = usb::UsbMatch::parse(ids);
        if (!config.usb)
            return Error{"malformed USB ids '" + ids +
                         "' in --source (expected VID:PID[:SERIAL] in hex, e.g. 8086:0b07)"};
    } else {
        return Error{"malformed live source '" + spec + "' (expected " + kLiveSourceSpecHelp + ")"};
    }
    if (Status s = parseOptions(parts, options, config); !s)
        return s.error();
    return config;
}

Expected<std::unique_ptr<Device>> openLiveSourceSpec(const std::string& spec) {
    auto config = parseLiveSourceSpec(spec);
    if (!config)
        return config.error();
    if (!config->depthNode.empty()) {
        if (Status s = checkDepthNode(config->depthNode); !s)
            return s.error();
    }
    return std::unique_ptr<Device>(std::make_unique<UvcDevice>(std::move(*config)));
}

} // namespace dc::devices
