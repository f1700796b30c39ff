#pragma once

#include "base/expected.h"
#include "base/mutex.h"
#include "devices/sensor_controls.h"
#include "devices/uvc/v4l2/controls.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "devices/uvc/v4l2/xu_controls.h"

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace dc::devices::v4l2 {

// One node's part of a preset: control keys (controlKey) and values as text, menus by their label, in the
// driver's order, which puts an auto control before the manual one it decides.
struct PresetNode {
    std::string card; // the node's card name when it was saved, for messages
    std::vector<std::pair<std::string, std::string>> values;
};

// A camera's control values, node by node in the order the camera lists its nodes: what `depthcloud
// controls --save` writes, and `--load` or a source's preset=FILE applies. Keyed by names rather than ids,
// so that a preset moves to another camera of the model and survives a driver that renumbers its private
// controls.
struct ControlPreset {
    std::string camera; // the --source it was saved from, for messages
    std::vector<PresetNode> nodes;
};

// What a preset keeps of a node: the values a person chooses, that is every control with a value that can
// be written, and not inactive (an auto control decides it) or volatile (the driver changes it).
PresetNode presetNodeOf(const std::string& card, const std::vector<V4l2Control>& controls);

std::string presetJson(const ControlPreset& preset);
// `path` names the preset in errors; an error says what is wrong where.
Expected<ControlPreset> parsePreset(std::string_view json, const std::string& path);
Expected<ControlPreset> readPreset(const std::string& path);

// Applies node i of the preset to nodePaths[i], value by value in the saved order. The node's controls are
// read again before each value, so that an auto control set before has made its partner settable. A value
// the camera refuses, or a control or node it lacks, is left out and told in the returned messages (one
// each, naming the node, the control and the value); everything else is set. `xu`'s node also takes its
// extension-unit controls by name.
std::vector<std::string> applyPreset(Syscalls& sys, const ControlPreset& preset,
                                     const std::vector<std::string>& nodePaths, const XuAccess& xu = {});

// A camera's nodes' controls for the window (devices::SensorControls), by path: each call opens the node.
// The node `xu` reaches lists its extension-unit controls after the driver's.
class V4l2SensorControls final : public SensorControls {
public:
    V4l2SensorControls(Syscalls& sys, std::vector<std::string> nodePaths, XuAccess xu = {})
        : sys_(sys), nodePaths_(std::move(nodePaths)), xu_(std::move(xu)) {}
    Expected<std::vector<SensorControlNode>> read() override;
    Status set(const std::string& path, std::uint32_t id, std::int64_t value) override;
    // The modes of the first node that offers Z16 or Y16 depth.
    std::vector<StreamMode> depthModes() override;
    // The image modes of the node that assignRoles() makes the camera's colour node, as the camera opens it.
    std::vector<StreamMode> colorModes() override;
    // Through V4L2_EVENT_CTRL, subscribed on a node of its own for every control of each node.
    bool changed() override;

private:
    Syscalls& sys_;
    const std::vector<std::string> nodePaths_;
    const XuAccess xu_;
    base::Mutex mutex_;
    std::optional<std::vector<V4l2Node>> watched_ DC_GUARDED_BY(mutex_);
};

} // namespace dc::devices::v4l2
