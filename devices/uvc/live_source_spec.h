#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "devices/uvc/uvc_device.h"

#include <memory>
#include <string>
#include <vector>

namespace dc::devices {

// The live sources of --source:
//   v4l2:/dev/videoN[:OPTION...]            a depth node (Z16, or Y16)
//   usb:VID:PID[:SERIAL][:OPTION...]        a USB camera by its ids (hex), found again after a replug
// OPTION: WxH[@FPS] (depth mode), format=Z16|Y16, scale=METERS_PER_UNIT, calib=FILE (one camera: OpenCV
// or ROS camera_info YAML; two sensors, depth and colour: OpenCV stereo YAML/JSON or Kalibr camchain),
// color=/dev/videoM|none, colormode=WxH[@FPS] and colorformat=YUYV|NV12|RGB3|MJPG|GREY (the colour node's
// mode; default: the calibrated colour size, else the depth's), watchdog=MS (default 2000), preset=FILE
// (control values set on open, as `depthcloud controls --save` writes them), pose= (checked and left to
// sourcePlacement).
inline constexpr const char* kLiveSourceSpecHelp = "v4l2:/dev/videoN[:OPTS] | usb:VID:PID[:SERIAL][:OPTS]";

bool isLiveSourceSpec(const std::string& spec);
// `spec` streaming the depth in `mode` (its WxH@FPS and format= replaced or added), the rest as it was.
Expected<std::string> withDepthMode(const std::string& spec, const StreamMode& mode);
// `spec` streaming its colour node in `mode` (colormode= and colorformat= replaced or added), the rest as
// it was; an error for a spec with color=none.
Expected<std::string> withColorMode(const std::string& spec, const StreamMode& mode);
// The camera's capture nodes in the order a preset's nodes go to them: every node of the USB camera a usb:
// source names (as `depthcloud devices` lists them), or a v4l2: source's depth node and its color= node.
Expected<std::vector<std::string>> cameraNodePaths(const UvcConfig& config);
// Parses without touching any device (a calibration file is read: a bad one is a bad argument).
Expected<UvcConfig> parseLiveSourceSpec(const std::string& spec);
// Parses, and opens a v4l2: node briefly: a path that is no video capture node (/dev/null, a typo) is a bad
// argument, refused here rather than when the device opens.
Expected<std::unique_ptr<Device>> openLiveSourceSpec(const std::string& spec);

} // namespace dc::devices
