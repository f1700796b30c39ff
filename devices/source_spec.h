#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "devices/source_pose.h"

#include <memory>
#include <string>

namespace dc::devices {

// The grammar of --source, shown in errors and --help.
inline constexpr const char* kSourceSpecHelp =
    "synthetic[:WxH[@FPS]][:motion][:exact][:rig=rgbd][:plane=DIST_M,TILT_DEG[,NOISE_MM]]"
    "[:view=X,Y,Z,QX,QY,QZ,QW] | "
    "replay:PATH[:loop][:paused][:speed=X][:calib=FILE] | "
    "v4l2:/dev/videoN[:OPTS] | usb:VID:PID[:SERIAL][:OPTS] | "
    "ros:DEPTH_TOPIC[:color=TOPIC|none][:info=TOPIC][:master=http://HOST:PORT][:tolerance=MS][:watchdog=MS]"
    "[:frame=FIXED_FRAME] | ros2:DEPTH_TOPIC[:domain=N][:the options of ros: but master=]; "
    "any of them [:pose=X,Y,Z,QX,QY,QZ,QW|:pose=FILE|:pose=FILE#CAMERA] (FILE: YAML or JSON "
    "`pose: [X, Y, Z, QX, QY, QZ, QW]`; with #CAMERA a Kalibr camchain or OpenCV extrinsics)";

// Parses a --source value and builds the device it names. Errors name the offending part. A pose= option is
// taken out before the kind sees the spec and places the device (Device::place).
Expected<std::unique_ptr<Device>> openSourceSpec(const std::string& spec);
// A live camera's spec streaming its depth in `mode`, the rest as it was; an error for other sources.
Expected<std::string> specWithDepthMode(const std::string& spec, const StreamMode& mode);
// The same for its colour node's mode; an error for other sources and for a camera streaming no colour.
Expected<std::string> specWithColorMode(const std::string& spec, const StreamMode& mode);

} // namespace dc::devices
