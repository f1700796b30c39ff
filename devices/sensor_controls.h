#pragma once

#include "base/expected.h"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dc::devices {

// One control of a camera as the window shows it: plain data, so that the UI includes no V4L2 header.
struct SensorControl {
    enum class Kind { Heading, Integer, Boolean, Menu, Button, Other };

    std::uint32_t id = 0;
    std::string name; // as the driver names it ("Exposure Time, Absolute")
    Kind kind = Kind::Other;
    std::int64_t minimum = 0;
    std::int64_t maximum = 0;
    std::int64_t step = 1;
    std::int64_t defaultValue = 0;
    std::optional<std::int64_t> value; // none for buttons, headings and values that cannot be read
    std::vector<std::pair<std::int64_t, std::string>> menu;
    bool readOnly = false;
    bool inactive = false; // an auto control decides it now: shown greyed
};

// The controls of one node of a camera (a RealSense has depth, infrared and colour nodes).
struct SensorControlNode {
    std::string path;
    std::string card;
    std::vector<SensorControl> controls;
};

// One way a camera's node can stream: its pixel format (depth "Z16", "Y16"; colour "YUYV", "MJPG"...), size
// and rate.
struct StreamMode {
    std::string format;
    int width = 0;
    int height = 0;
    double fps = 0.0;

    bool operator==(const StreamMode&) const = default;
};

// What the window may do to a camera's controls. A device that has none gives no surface. Safe to use from
// any thread while the device streams: an implementation holds only what does not change and opens the
// camera's nodes for each call.
class SensorControls {
public:
    virtual ~SensorControls() = default;
    // Every node's controls and their values now.
    virtual Expected<std::vector<SensorControlNode>> read() = 0;
    // Sets one control; an error names the node, the control and the value.
    virtual Status set(const std::string& path, std::uint32_t id, std::int64_t value) = 0;
    // Whether a control changed (by this program, another such as v4l2-ctl, or the driver's auto controls)
    // since the last call. The first call starts watching and says false.
    virtual bool changed() { return false; }
    // Every depth format, size and rate the camera's depth node offers (none: it cannot say).
    virtual std::vector<StreamMode> depthModes() { return {}; }
    // Every image format, size and rate the camera's colour node offers (none: it has none or cannot say).
    virtual std::vector<StreamMode> colorModes() { return {}; }
};

} // namespace dc::devices
