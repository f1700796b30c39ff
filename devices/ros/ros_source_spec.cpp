#include "devices/ros/ros_source_spec.h"

#include "devices/ros/dds_subscription.h"
#include "devices/ros/ros_device.h"
#include "devices/ros/ros_image.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_node.h"

#include <cctype>
#include <charconv>
#include <sstream>
#include <vector>

namespace dc::devices::ros {

namespace {

// Splits at ':' but keeps master=http://HOST:PORT whole: its own colons are not separators.
std::vector<std::string> splitOptions(const std::string& spec) {
    std::vector<std::string> parts;
    std::stringstream in(spec);
    for (std::string part; std::getline(in, part, ':');) {
        const bool continuesUri =
            !parts.empty() && parts.back().starts_with("master=") &&
            (part.starts_with("//") || (!part.empty() && std::isdigit(static_cast<unsigned char>(part[0]))));
        if (continuesUri)
            parts.back() += ":" + part;
        else
            parts.push_back(part);
    }
    return parts;
}

// "--source ros:" or "--source ros2:", for messages.
std::string kindOf(const RosSourceConfig& config) {
    return config.ros2 ? "--source ros2:" : "--source ros:";
}

std::string helpOf(const RosSourceConfig& config) {
    return config.ros2 ? kRos2SourceSpecHelp : kRosSourceSpecHelp;
}

// ROS graph names: letters, digits, '_' and '/'; a relative name is taken from the root namespace.
Expected<std::string> topicName(const std::string& name, const std::string& what,
                                const RosSourceConfig& config) {
    const bool valid =
        !name.empty() && name != "/" && name.back() != '/' && name.find("//") == std::string::npos &&
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_/") ==
            std::string::npos;
    if (!valid)
        return Error{"'" + name + "' in " + kindOf(config) + " is not a ROS name (" + what + ")"};
    return name.front() == '/' ? name : "/" + name;
}

Status milliseconds(const std::string& key, const std::string& value, const RosSourceConfig& config,
                    std::chrono::milliseconds& out) {
    long ms = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), ms);
    if (value.empty() || ec != std::errc() || end != value.data() + value.size() || ms <= 0 || ms > 600'000)
        return Error{key + "=" + value + " in " + kindOf(config) + " expected milliseconds, e.g. " + key +
                     "=20"};
    out = std::chrono::milliseconds(ms);
    return {};
}

Status domainId(const std::string& value, RosSourceConfig& config) {
    int domain = -1;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), domain);
    if (value.empty() || ec != std::errc() || end != value.data() + value.size() || domain < 0 ||
        domain > kMaxRosDomain)
        return Error{"domain=" + value + " in --source ros2: expected a ROS domain id, 0.." +
                     std::to_string(kMaxRosDomain)};
    config.domain = domain;
    return {};
}

Status parseOption(const std::string& part, RosSourceConfig& config, bool& colorGiven, bool& infoGiven) {
    const auto eq = part.find('=');
    const std::string key = part.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : part.substr(eq + 1);
    const auto unknown = [&] {
        return Error{"unknown option '" + part + "' in " + kindOf(config) + " (expected " + helpOf(config) +
                     ")"};
    };
    if (eq == std::string::npos)
        return unknown();
    if (key == "color") {
        colorGiven = true;
        if (value == "none") {
            config.colorTopic.clear();
            return {};
        }
        auto topic = topicName(value, "color=", config);
        if (!topic)
            return topic.error();
        config.colorTopic = *topic;
    } else if (key == "info") {
        auto topic = topicName(value, "info=", config);
        if (!topic)
            return topic.error();
        config.infoTopic = *topic;
        infoGiven = true;
    } else if (key == "master" && !config.ros2) {
        if (auto uri = parseMasterUri(value); !uri)
            return Error{"master=" + value + " in --source ros: " + uri.error().message};
        config.masterUri = value;
    } else if (key == "domain" && config.ros2) {
        return domainId(value, config);
    } else if (key == "frame") {
        auto frame = topicName(value, "frame=", config);
        if (!frame)
            return frame.error();
        config.fixedFrame = frame->substr(1); // tf2 frame ids carry no leading slash
    } else if (key == "tolerance") {
        return milliseconds(key, value, config, config.pairTolerance);
    } else if (key == "watchdog") {
        return milliseconds(key, value, config, config.watchdog);
    } else {
        return unknown();
    }
    return {};
}

} // namespace

DerivedTopics deriveTopics(const std::string& topic) {
    // A compressed depth topic's camera_info is its raw topic's; its colour is taken compressed too (a link
    // that needs depth compressed needs colour so as well).
    const std::string depthTopic = withoutTransport(topic);
    const std::string colorTransport = depthTopic != topic ? "/compressed" : "";
    const auto slash = depthTopic.rfind('/');
    const std::string ns = slash == std::string::npos ? std::string() : depthTopic.substr(0, slash);
    DerivedTopics topics{{}, ns + "/camera_info"};
    const auto parentSlash = ns.rfind('/');
    if (parentSlash == std::string::npos)
        return topics;
    if (ns.substr(parentSlash + 1).find("depth") != std::string::npos)
        topics.color = ns.substr(0, parentSlash) + "/color/image_raw" + colorTransport;
    return topics;
}

namespace {

Expected<RosSourceConfig> parseSpec(const std::string& spec, bool ros2) {
    RosSourceConfig config;
    config.ros2 = ros2;
    const std::vector<std::string> parts = splitOptions(spec);
    if (parts.empty() || parts[0].empty())
        return Error{kindOf(config) + " needs a depth topic (expected " + helpOf(config) + ")"};
    auto depth = topicName(parts[0], "the depth topic", config);
    if (!depth)
        return depth.error();
    config.depthTopic = *depth;
    bool colorGiven = false;
    bool infoGiven = false;
    for (std::size_t i = 1; i < parts.size(); ++i)
        if (Status s = parseOption(parts[i], config, colorGiven, infoGiven); !s)
            return s.error();
    const DerivedTopics derived = deriveTopics(config.depthTopic);
    if (!colorGiven)
        config.colorTopic = derived.color;
    if (!infoGiven)
        config.infoTopic = derived.info;
    return config;
}

} // namespace

Expected<RosSourceConfig> parseRosSourceSpec(const std::string& spec) {
    return parseSpec(spec, false);
}

Expected<RosSourceConfig> parseRos2SourceSpec(const std::string& spec) {
    return parseSpec(spec, true);
}

Expected<std::unique_ptr<Device>> openRosSourceSpec(const std::string& spec) {
    auto config = parseRosSourceSpec(spec);
    if (!config)
        return config.error();
    auto link = makeMasterLink(config->masterUri);
    return std::unique_ptr<Device>(std::make_unique<RosDevice>(std::move(*config), std::move(link)));
}

Expected<std::unique_ptr<Device>> openRos2SourceSpec(const std::string& spec) {
    auto config = parseRos2SourceSpec(spec);
    if (!config)
        return config.error();
    if (config->domain < 0) {
        auto domain = rosDomainFromEnvironment();
        if (!domain)
            return domain.error();
        config->domain = *domain;
    }
    auto link = makeDdsLink(config->domain);
    return std::unique_ptr<Device>(std::make_unique<RosDevice>(std::move(*config), std::move(link)));
}

} // namespace dc::devices::ros
