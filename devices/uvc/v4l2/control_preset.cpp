#include "devices/uvc/v4l2/control_preset.h"

#include "base/files.h"
#include "devices/uvc/v4l2/node_probe.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "devices/uvc/v4l2/xu_controls.h"

#include <linux/videodev2.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>

namespace dc::devices::v4l2 {

namespace {

constexpr const char* kFormat = "depthcloud-controls-preset";
constexpr int kVersion = 1;

std::string valueText(const V4l2Control& c, std::int64_t value) {
    const auto entry =
        std::find_if(c.menu.begin(), c.menu.end(), [value](const MenuEntry& e) { return e.index == value; });
    if (c.type == V4L2_CTRL_TYPE_MENU && entry != c.menu.end())
        return entry->label;
    return std::to_string(value);
}

Expected<PresetNode> parseNode(const nlohmann::json& node, const std::string& where) {
    if (!node.is_object() || !node.contains("controls") || !node["controls"].is_array())
        return Error{where + ": expected an object with a \"controls\" array"};
    PresetNode out;
    if (const auto card = node.find("card"); card != node.end() && card->is_string())
        out.card = card->get<std::string>();
    for (std::size_t i = 0; i < node["controls"].size(); ++i) {
        const nlohmann::json& c = node["controls"][i];
        const std::string at = where + ".controls[" + std::to_string(i) + "]";
        if (!c.is_object() || !c.contains("name") || !c["name"].is_string() || !c.contains("value"))
            return Error{at + ": expected {\"name\": TEXT, \"value\": NUMBER or TEXT}"};
        const nlohmann::json& value = c["value"];
        if (!value.is_number_integer() && !value.is_string())
            return Error{at + ": the value of '" + c["name"].get<std::string>() +
                         "' must be an integer or a menu entry's label"};
        out.values.emplace_back(c["name"].get<std::string>(),
                                value.is_string() ? value.get<std::string>() : value.dump());
    }
    return out;
}

// One value set on an open node, or why not (naming the node and the control).
Status applyValue(Syscalls& sys, const V4l2Node& node, const std::string& key, const std::string& text,
                  const XuAccess& xu) {
    auto controls = queryNodeControls(sys, node.fd(), node.path(), xu);
    if (!controls)
        return controls.error();
    const auto control = std::find_if(controls->begin(), controls->end(), [&key](const V4l2Control& c) {
        return !c.isClass() && controlKey(c.name) == key;
    });
    if (control == controls->end())
        return Error{node.path() + ": no control named '" + key + "'"};
    auto value = parseControlValue(*control, text);
    if (!value)
        return Error{node.path() + ": " + value.error().message};
    if (Status s = checkControlValue(*control, *value); !s)
        return Error{node.path() + ": " + s.error().message};
    return setNodeControl(sys, node.fd(), node.path(), *control, *value);
}

SensorControl::Kind kindOf(const V4l2Control& c) {
    using Kind = SensorControl::Kind;
    switch (c.type) {
    case V4L2_CTRL_TYPE_CTRL_CLASS:
        return Kind::Heading;
    case V4L2_CTRL_TYPE_INTEGER:
    case V4L2_CTRL_TYPE_INTEGER64:
    case V4L2_CTRL_TYPE_BITMASK:
        return Kind::Integer;
    case V4L2_CTRL_TYPE_BOOLEAN:
        return Kind::Boolean;
    case V4L2_CTRL_TYPE_MENU:
    case V4L2_CTRL_TYPE_INTEGER_MENU:
        return Kind::Menu;
    case V4L2_CTRL_TYPE_BUTTON:
        return Kind::Button;
    default:
        return Kind::Other;
    }
}

SensorControl sensorControlOf(const V4l2Control& c) {
    SensorControl out{
        c.id,           c.name,  kindOf(c), c.minimum,    c.maximum,   static_cast<std::int64_t>(c.step),
        c.defaultValue, c.value, {},        c.readOnly(), c.inactive()};
    for (const MenuEntry& e : c.menu)
        out.menu.emplace_back(e.index, e.label);
    return out;
}

// Opens the node at `path` into `node` and reads its controls, with the XU controls `xu` gives it.
Expected<std::vector<V4l2Control>> openControls(V4l2Node& node, Syscalls& sys, const std::string& path,
                                                const XuAccess& xu) {
    if (const int r = node.open(path); r < 0)
        return Error{path + ": cannot open: " + std::strerror(-r)};
    return queryNodeControls(sys, node.fd(), path, xu);
}

} // namespace

Expected<std::vector<SensorControlNode>> V4l2SensorControls::read() {
    std::vector<SensorControlNode> nodes;
    for (const std::string& path : nodePaths_) {
        V4l2Node node(sys_);
        auto controls = openControls(node, sys_, path, xu_);
        if (!controls)
            return controls.error();
        SensorControlNode out{path, node.capability().card, {}};
        for (const V4l2Control& c : *controls)
            out.controls.push_back(sensorControlOf(c));
        nodes.push_back(std::move(out));
    }
    return nodes;
}

Status V4l2SensorControls::set(const std::string& path, std::uint32_t id, std::int64_t value) {
    V4l2Node node(sys_);
    auto controls = openControls(node, sys_, path, xu_);
    if (!controls)
        return controls.error();
    const auto control =
        std::find_if(controls->begin(), controls->end(), [id](const V4l2Control& c) { return c.id == id; });
    if (control == controls->end())
        return Error{path + ": has no control " + std::to_string(id)};
    if (Status s = checkControlValue(*control, value); !s)
        return Error{path + ": " + s.error().message};
    return setNodeControl(sys_, node.fd(), path, *control, value);
}

bool V4l2SensorControls::changed() {
    const base::MutexLock lock(mutex_);
    if (!watched_) {
        watched_.emplace();
        for (const std::string& path : nodePaths_) {
            // V4L2_EVENT_CTRL covers only the driver's controls: an XU control changes unseen.
            V4l2Node node(sys_);
            auto controls = openControls(node, sys_, path, {});
            if (!controls)
                continue;
            std::vector<std::uint32_t> ids;
            for (const V4l2Control& c : *controls)
                if (!c.isClass())
                    ids.push_back(c.id);
            if (node.subscribeControlChanges(ids) == 0)
                watched_->push_back(std::move(node));
        }
        return false;
    }
    bool any = false;
    for (V4l2Node& node : *watched_)
        any |= node.takeControlChanges();
    return any;
}

std::vector<StreamMode> V4l2SensorControls::depthModes() {
    for (const std::string& path : nodePaths_) {
        V4l2Node node(sys_);
        if (node.open(path) < 0)
            continue;
        std::vector<StreamMode> modes;
        for (const std::uint32_t fourcc : node.formats()) {
            if (fourcc != V4L2_PIX_FMT_Z16 && fourcc != V4L2_PIX_FMT_Y16)
                continue;
            const std::string format = fourcc == V4L2_PIX_FMT_Z16 ? "Z16" : "Y16";
            for (const V4l2Mode& m : node.modes(fourcc))
                for (const double fps : m.framesPerSecond)
                    modes.push_back({format, m.width, m.height, fps});
        }
        if (!modes.empty())
            return modes;
    }
    return {};
}

std::vector<StreamMode> V4l2SensorControls::colorModes() {
    std::vector<ProbedNode> probed;
    for (const std::string& path : nodePaths_) {
        int error = 0;
        if (auto node = probeNode(sys_, path, error))
            probed.push_back(std::move(*node));
    }
    const std::string color = assignRoles(probed).color;
    std::vector<StreamMode> modes;
    for (const ProbedNode& node : probed) {
        if (node.path != color)
            continue;
        for (const V4l2Mode& m : node.modes) {
            const FormatRole role = roleOf(m.fourcc);
            if (role != FormatRole::Color && role != FormatRole::Guide)
                continue;
            for (const double fps : m.framesPerSecond)
                modes.push_back({fourccToString(m.fourcc), m.width, m.height, fps});
        }
    }
    return modes;
}

PresetNode presetNodeOf(const std::string& card, const std::vector<V4l2Control>& controls) {
    PresetNode node{card, {}};
    for (const V4l2Control& c : controls) {
        const bool chosen = c.settable() && c.value && !c.readOnly() && !c.inactive() &&
                            c.type != V4L2_CTRL_TYPE_BUTTON && (c.flags & V4L2_CTRL_FLAG_VOLATILE) == 0;
        if (chosen)
            node.values.emplace_back(controlKey(c.name), valueText(c, *c.value));
    }
    return node;
}

std::string presetJson(const ControlPreset& preset) {
    nlohmann::json nodes = nlohmann::json::array();
    for (const PresetNode& node : preset.nodes) {
        nlohmann::json controls = nlohmann::json::array();
        for (const auto& [key, text] : node.values) {
            // Integers as numbers, menu entries by their label.
            const bool number = !text.empty() && text.find_first_not_of("-0123456789") == std::string::npos;
            controls.push_back(
                {{"name", key}, {"value", number ? nlohmann::json::parse(text) : nlohmann::json(text)}});
        }
        nodes.push_back({{"card", node.card}, {"controls", controls}});
    }
    const nlohmann::json out{
        {"format", kFormat}, {"version", kVersion}, {"camera", preset.camera}, {"nodes", nodes}};
    return out.dump(2) + "\n";
}

Expected<ControlPreset> parsePreset(std::string_view json, const std::string& path) {
    const nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_discarded())
        return Error{path + ": not JSON"};
    if (!doc.is_object() || doc.value("format", "") != kFormat)
        return Error{path + ": not a depthcloud controls preset (no \"format\": \"" + std::string(kFormat) +
                     "\")"};
    if (!doc["version"].is_number_integer() || doc["version"].get<int>() > kVersion)
        return Error{path + ": preset version " + doc["version"].dump() +
                     " is newer than this depthcloud's " + std::to_string(kVersion)};
    if (!doc.contains("nodes") || !doc["nodes"].is_array())
        return Error{path + ": expected a \"nodes\" array"};
    ControlPreset preset;
    if (doc.contains("camera") && doc["camera"].is_string())
        preset.camera = doc["camera"].get<std::string>();
    for (std::size_t i = 0; i < doc["nodes"].size(); ++i) {
        auto node = parseNode(doc["nodes"][i], path + ": nodes[" + std::to_string(i) + "]");
        if (!node)
            return node.error();
        preset.nodes.push_back(std::move(*node));
    }
    return preset;
}

Expected<ControlPreset> readPreset(const std::string& path) {
    auto bytes = base::readFile(path);
    if (!bytes)
        return bytes.error();
    return parsePreset(std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()), path);
}

std::vector<std::string> applyPreset(Syscalls& sys, const ControlPreset& preset,
                                     const std::vector<std::string>& nodePaths, const XuAccess& xu) {
    std::vector<std::string> refused;
    for (std::size_t i = 0; i < preset.nodes.size(); ++i) {
        const PresetNode& saved = preset.nodes[i];
        if (i >= nodePaths.size()) {
            refused.push_back("the preset's node " + std::to_string(i + 1) + " (" + saved.card +
                              ") has no node here to go to");
            continue;
        }
        V4l2Node node(sys);
        if (const int r = node.open(nodePaths[i]); r < 0) {
            refused.push_back(nodePaths[i] + ": cannot open: " + std::strerror(-r));
            continue;
        }
        for (const auto& [key, text] : saved.values)
            if (Status s = applyValue(sys, node, key, text, xu); !s)
                refused.push_back(s.error().message);
    }
    return refused;
}

} // namespace dc::devices::v4l2
