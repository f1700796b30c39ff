#include "tool/controls_command.h"

#include "base/files.h"
#include "devices/uvc/live_source_spec.h"
#include "devices/uvc/uvc_device.h"
#include "devices/uvc/v4l2/control_preset.h"
#include "devices/uvc/v4l2/controls.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "devices/uvc/v4l2/xu_controls.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>

namespace dc::tool {

namespace {

namespace v4l2 = devices::v4l2;

struct NodeControls {
    std::string path;
    std::string card;
    std::vector<v4l2::V4l2Control> controls;
};

struct Failure {
    int code;
    std::string message;
};

std::optional<Failure> readControls(const std::vector<std::string>& paths, const v4l2::XuAccess& xu,
                                    std::vector<NodeControls>& out) {
    out.clear();
    for (const std::string& path : paths) {
        v4l2::V4l2Node node;
        if (const int r = node.open(path); r < 0)
            return Failure{kExitFailure, path + ": cannot open: " + std::strerror(-r)};
        auto controls = v4l2::queryNodeControls(v4l2::systemSyscalls(), node.fd(), path, xu);
        if (!controls)
            return Failure{kExitFailure, controls.error().message};
        out.push_back({path, node.capability().card, std::move(*controls)});
    }
    return std::nullopt;
}

// Checks every --set against the controls before any is set: a bad one changes nothing.
std::optional<Failure> applySets(const std::vector<std::string>& sets,
                                 const std::vector<NodeControls>& nodes) {
    struct Change {
        const NodeControls* node;
        const v4l2::V4l2Control* control;
        std::int64_t value;
    };
    std::vector<Change> changes;
    for (const std::string& set : sets) {
        const auto equals = set.find('=');
        const std::string key = v4l2::controlKey(set.substr(0, equals));
        std::optional<Change> change;
        for (const NodeControls& node : nodes)
            for (const v4l2::V4l2Control& c : node.controls)
                if (!change && !c.isClass() && v4l2::controlKey(c.name) == key)
                    change = Change{&node, &c, 0};
        if (equals == std::string::npos || !change)
            return Failure{
                kExitBadArguments,
                "--set " + set + ": " +
                    (equals == std::string::npos ? "expected NAME=VALUE" : "no control named '" + key + "'")};
        auto value = v4l2::parseControlValue(*change->control, set.substr(equals + 1));
        if (!value)
            return Failure{kExitBadArguments, "--set " + set + ": " + value.error().message};
        if (Status s = v4l2::checkControlValue(*change->control, *value); !s)
            return Failure{kExitBadArguments, "--set " + set + ": " + s.error().message};
        change->value = *value;
        changes.push_back(*change);
    }
    for (const Change& c : changes) {
        v4l2::V4l2Node node;
        if (const int r = node.open(c.node->path); r < 0)
            return Failure{kExitFailure, c.node->path + ": cannot open: " + std::strerror(-r)};
        if (Status s =
                v4l2::setNodeControl(v4l2::systemSyscalls(), node.fd(), c.node->path, *c.control, c.value);
            !s)
            return Failure{kExitFailure, s.error().message};
    }
    return std::nullopt;
}

nlohmann::json toJson(const std::vector<NodeControls>& nodes) {
    nlohmann::json out = nlohmann::json::array();
    for (const NodeControls& node : nodes) {
        nlohmann::json controls = nlohmann::json::array();
        for (const v4l2::V4l2Control& c : node.controls) {
            nlohmann::json menu = nlohmann::json::array();
            for (const v4l2::MenuEntry& e : c.menu)
                menu.push_back({{"index", e.index}, {"label", e.label}});
            controls.push_back({{"id", c.id},
                                {"key", v4l2::controlKey(c.name)},
                                {"name", c.name},
                                {"type", v4l2::controlTypeName(c.type)},
                                {"min", c.minimum},
                                {"max", c.maximum},
                                {"step", c.step},
                                {"default", c.defaultValue},
                                {"flags", v4l2::controlFlagNames(c)},
                                {"menu", menu},
                                {"value", c.value ? nlohmann::json(*c.value) : nlohmann::json(nullptr)}});
        }
        out.push_back({{"node", node.path}, {"card", node.card}, {"controls", controls}});
    }
    return nlohmann::json{{"nodes", out}};
}

void printText(const std::vector<NodeControls>& nodes) {
    for (const NodeControls& node : nodes) {
        std::printf("%s  %s\n", node.path.c_str(), node.card.c_str());
        for (const v4l2::V4l2Control& c : node.controls) {
            if (c.isClass()) {
                std::printf("  %s\n", c.name.c_str());
                continue;
            }
            std::string flags;
            for (const std::string& f : v4l2::controlFlagNames(c))
                flags += " " + f;
            const std::string value = c.value ? std::to_string(*c.value) : "-";
            std::printf("    %-32s %-8s %lld..%lld step %llu default %lld: %s%s\n",
                        v4l2::controlKey(c.name).c_str(), v4l2::controlTypeName(c.type),
                        static_cast<long long>(c.minimum), static_cast<long long>(c.maximum),
                        static_cast<unsigned long long>(c.step), static_cast<long long>(c.defaultValue),
                        value.c_str(), flags.c_str());
            for (const v4l2::MenuEntry& e : c.menu)
                std::printf("      %lld: %s\n", static_cast<long long>(e.index), e.label.c_str());
        }
    }
}

std::string presetJson(const std::string& source, const std::vector<NodeControls>& nodes) {
    v4l2::ControlPreset preset{source, {}};
    for (const NodeControls& node : nodes)
        preset.nodes.push_back(v4l2::presetNodeOf(node.card, node.controls));
    return v4l2::presetJson(preset);
}

// What --source names, or why it names no camera (a bad argument either way).
Expected<devices::UvcConfig> parseSource(const ControlsOptions& o) {
    if (!devices::isLiveSourceSpec(o.source))
        return Error{"--source " + o.source + ": controls need a live camera (" +
                     devices::kLiveSourceSpecHelp + ")"};
    auto config = devices::parseLiveSourceSpec(o.source);
    if (!config)
        return Error{"--source: " + config.error().message};
    return std::move(*config);
}

} // namespace

CLI::App* addControlsCommand(CLI::App& app, ControlsOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "controls", "list a V4L2 camera's controls (range, default, flags, value) and set them");
    cmd->add_option("--source", o.source, devices::kLiveSourceSpecHelp)->required();
    cmd->add_option("--set", o.sets, "set a control, NAME=VALUE (NAME as listed; repeatable)");
    cmd->add_flag("--json", o.json, "print the listing as JSON");
    cmd->add_option("--load", o.load, "apply a preset (JSON, as --save writes it) before any --set");
    cmd->add_option("--save", o.save, "write the values (after --load and --set) as a preset");
    cmd->add_flag("--overwrite", o.overwrite, "let --save replace an existing file");
    return cmd;
}

int runControls(const ControlsOptions& o) {
    const auto fail = [](const Failure& f) {
        std::fprintf(stderr, "depthcloud: error: %s\n", f.message.c_str());
        return f.code;
    };
    const auto config = parseSource(o);
    if (!config)
        return fail({kExitBadArguments, config.error().message});
    std::optional<v4l2::ControlPreset> preset;
    if (!o.load.empty()) {
        auto loaded = v4l2::readPreset(o.load);
        if (!loaded)
            return fail({kExitBadArguments, "--load: " + loaded.error().message});
        preset = std::move(*loaded);
    }
    std::error_code ec;
    if (!o.save.empty() && !o.overwrite && std::filesystem::exists(o.save, ec))
        return fail(
            {kExitBadArguments, "--save " + o.save + " already exists (pass --overwrite to replace it)"});
    const auto paths = devices::cameraNodePaths(*config);
    if (!paths)
        return fail({kExitFailure, paths.error().message});
    std::vector<NodeControls> nodes;
    // A known camera's extension-unit controls (a RealSense's emitter, laser power) are listed, set and
    // saved with the driver's.
    const v4l2::XuAccess xu = devices::extensionUnitAccess(v4l2::systemSyscalls(), *config, *paths);
    if (auto f = readControls(*paths, xu, nodes))
        return fail(*f);
    std::vector<std::string> refused;
    if (preset)
        refused = v4l2::applyPreset(v4l2::systemSyscalls(), *preset, *paths, xu);
    if (!o.sets.empty())
        if (auto f = applySets(o.sets, nodes))
            return fail(*f);
    if (preset || !o.sets.empty())
        if (auto f = readControls(*paths, xu, nodes))
            return fail(*f);
    if (!o.save.empty())
        if (Status s = base::writeTextFile(o.save, presetJson(o.source, nodes)); !s)
            return fail({kExitFailure, "--save: " + s.error().message});
    if (o.json)
        std::printf("%s\n", toJson(nodes).dump(2).c_str());
    else
        printText(nodes);
    for (const std::string& message : refused)
        std::fprintf(stderr, "depthcloud: error: --load %s: %s\n", o.load.c_str(), message.c_str());
    return refused.empty() ? kExitOk : kExitFailure;
}

} // namespace dc::tool
