#include "devices/source_spec.h"

#include "devices/replay/replay_spec.h"
#include "devices/source_pose.h"
#include "devices/synthetic/synthetic_device.h"
#include "devices/uvc/live_source_spec.h"
#ifdef DC_HAVE_ROS
#include "devices/ros/ros_source_spec.h"
#endif

#include <charconv>
#include <sstream>
#include <vector>

namespace dc::devices {

namespace {

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, sep);)
        parts.push_back(part);
    return parts;
}

template <class T> bool parseNumber(const std::string& text, T& out) {
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end && !text.empty();
}

// "WxH" or "WxH@FPS".
Status parseMode(const std::string& mode, SyntheticConfig& config) {
    const Error bad{"malformed mode '" + mode + "' in --source (expected WxH or WxH@FPS, e.g. 640x480@30)"};
    const auto at = mode.find('@');
    const std::string size = mode.substr(0, at);
    const auto x = size.find('x');
    if (x == std::string::npos || !parseNumber(size.substr(0, x), config.depthWidth) ||
        !parseNumber(size.substr(x + 1), config.depthHeight) || config.depthWidth <= 0 ||
        config.depthHeight <= 0)
        return bad;
    if (at != std::string::npos && (!parseNumber(mode.substr(at + 1), config.fps) || !(config.fps > 0.0)))
        return bad;
    return {};
}

// "DISTANCE_M,TILT_DEG[,NOISE_MM]": a flat target (SyntheticConfig::flatTarget).
Expected<FlatTarget> parseFlatTarget(const std::string& text) {
    const Error bad{"malformed plane='" + text +
                    "' in --source (expected DISTANCE_M,TILT_DEG[,NOISE_MM], e.g. plane=1.5,10,1)"};
    const std::vector<std::string> v = split(text, ',');
    FlatTarget t;
    if (v.size() < 2 || v.size() > 3 || !parseNumber(v[0], t.distanceMeters) ||
        !parseNumber(v[1], t.tiltDegrees) || (v.size() == 3 && !parseNumber(v[2], t.noiseMm)))
        return bad;
    return t;
}

// The camera's kind comes first: the other options adjust it.
SyntheticConfig syntheticBase(const std::vector<std::string>& parts) {
    for (std::size_t i = 1; i < parts.size(); ++i)
        if (parts[i] == "rig=rgbd")
            return syntheticRigConfig();
    return {};
}

Expected<std::unique_ptr<Device>> openSynthetic(const std::vector<std::string>& parts) {
    SyntheticConfig config = syntheticBase(parts);
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const std::string& p = parts[i];
        if (p == "rig=rgbd")
            continue;
        if (p.starts_with("rig="))
            return Error{"unknown rig '" + p.substr(4) + "' in --source (expected rig=rgbd)"};
        if (p == "motion" && config.rig) {
            config.motion = true;
        } else if (p == "motion") {
            config.motion = true;
            // A moving camera re-renders its image every frame; VGA keeps that off the critical path.
            config.cameraWidth = 640;
            config.cameraHeight = 480;
        } else if (p == "exact") {
            config.noise = false;
        } else if (p.starts_with("plane=")) {
            auto target = parseFlatTarget(p.substr(6));
            if (!target)
                return target.error();
            config.flatTarget = *target;
        } else if (p.starts_with("view=")) {
            auto view = parsePoseValue(p.substr(5));
            if (!view)
                return Error{p + " in --source: " + view.error().message};
            config.view = *view;
        } else if (Status s = parseMode(p, config); !s) {
            return s.error();
        }
    }
    if (Status s = checkSyntheticConfig(config); !s)
        return s.error();
    return std::unique_ptr<Device>(std::make_unique<SyntheticDevice>(config));
}

Expected<std::unique_ptr<Device>> openUnplaced(const std::string& spec) {
    const std::vector<std::string> parts = split(spec, ':');
    if (!parts.empty() && parts[0] == "synthetic")
        return openSynthetic(parts);
    if (isLiveSourceSpec(spec))
        return openLiveSourceSpec(spec);
    if (spec.starts_with("replay:"))
        return replay::openReplaySpec(spec.substr(7));
#ifdef DC_HAVE_ROS
    if (spec.starts_with("ros:"))
        return ros::openRosSourceSpec(spec.substr(4));
    if (spec.starts_with("ros2:"))
        return ros::openRos2SourceSpec(spec.substr(5));
#endif
    return Error{"unknown source '" + spec + "' (expected " + kSourceSpecHelp + ")"};
}

} // namespace

Expected<std::unique_ptr<Device>> openSourceSpec(const std::string& given) {
    auto placement = sourcePlacement(given);
    if (!placement)
        return placement.error();
    auto device = openUnplaced(placement->spec);
    if (device && placement->cameraToWorld)
        (*device)->place(*placement->cameraToWorld);
    return device;
}

Expected<std::string> specWithDepthMode(const std::string& spec, const StreamMode& mode) {
    if (!isLiveSourceSpec(spec))
        return Error{spec + " is not a live camera: its depth mode is its recording's"};
    return withDepthMode(spec, mode);
}

Expected<std::string> specWithColorMode(const std::string& spec, const StreamMode& mode) {
    if (!isLiveSourceSpec(spec))
        return Error{spec + " is not a live camera: its colour mode is its recording's"};
    return withColorMode(spec, mode);
}

} // namespace dc::devices
