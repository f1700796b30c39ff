#include "devices/replay/replay_spec.h"

#include "devices/replay/replay_device.h"
#include "devices/replay/text_fields.h"
#include "devices/source_pose.h"

namespace dc::devices::replay {

namespace {

// Applies one trailing ":option"; false when `option` is not one (then it belongs to the path).
bool applyOption(const std::string& option, ReplayOptions& replay, ReplayOpenOptions& open,
                 std::string& problem) {
    if (option == "loop") {
        replay.loop = true;
    } else if (option == "paused") {
        replay.startPlaying = false;
    } else if (option.starts_with("speed=")) {
        double speed = 0.0;
        if (!parseFiniteDouble(option.substr(6), speed) || speed < ReplayControl::kMinSpeed ||
            speed > ReplayControl::kMaxSpeed)
            problem = "replay speed '" + option.substr(6) + "' must be between 0.25 and 4";
        replay.speed = speed;
    } else if (option.starts_with("calib=")) {
        open.calibrationPath = option.substr(6);
        if (open.calibrationPath.empty())
            problem = "calib= needs a calibration file";
    } else if (option.starts_with("topics=")) {
        const std::string topics = option.substr(7);
        const auto comma = topics.find(',');
        open.depthTopic = topics.substr(0, comma);
        open.colorTopic = comma == std::string::npos ? "" : topics.substr(comma + 1);
        if (open.depthTopic.empty())
            problem = "topics= needs a depth image topic (topics=DEPTH[,COLOR])";
    } else {
        return false;
    }
    return true;
}

struct ParsedSpec {
    std::string path;
    ReplayOptions replay;
    ReplayOpenOptions open;
};

Expected<ParsedSpec> parseSpec(const std::string& rest) {
    ParsedSpec spec{rest, {}, {}};
    std::string problem;
    for (auto colon = spec.path.rfind(':'); colon != std::string::npos; colon = spec.path.rfind(':')) {
        if (!applyOption(spec.path.substr(colon + 1), spec.replay, spec.open, problem))
            break;
        spec.path.resize(colon);
    }
    if (!problem.empty())
        return Error{problem};
    if (spec.path.empty())
        return Error{std::string("replay needs a path (") + kReplaySpecHelp + ")"};
    return spec;
}

} // namespace

Expected<std::unique_ptr<Device>> openReplaySpec(const std::string& rest) {
    auto spec = parseSpec(rest);
    if (!spec)
        return spec.error();
    auto source = openReplaySource(spec->path, spec->open);
    if (!source)
        return source.error();
    return std::unique_ptr<Device>(std::make_unique<ReplayDevice>(std::move(*source), spec->replay));
}

Expected<std::unique_ptr<ReplaySource>> openReplaySpecSource(const std::string& given) {
    // Where the source sits in the world is its reader's business, not the source's.
    auto placement = sourcePlacement(given);
    if (!placement)
        return placement.error();
    const std::string& text = placement->spec;
    auto spec = parseSpec(text.starts_with("replay:") ? text.substr(7) : text);
    if (!spec)
        return spec.error();
    return openReplaySource(spec->path, spec->open);
}

} // namespace dc::devices::replay
