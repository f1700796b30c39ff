#include "devices/ros/mcap_source.h"

#include "devices/ros/cdr.h"
#include "devices/ros/db3_store.h"
#include "devices/ros/mcap_reader.h"
#include "devices/ros/message_store.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace dc::devices::ros {

namespace {

// ROS 2 spells its types pkg/msg/Type; the replay matches ROS 1's pkg/Type.
std::string ros1TypeName(const McapChannel& channel) {
    std::string type = channel.schemaName;
    if (const auto at = type.find("/msg/"); at != std::string::npos)
        type.erase(at, 4);
    // Only CDR is decoded: another encoding keeps a name no replay matches.
    return channel.messageEncoding == "cdr" ? type : type + " (" + channel.messageEncoding + ")";
}

class McapStore final : public MessageStore {
public:
    explicit McapStore(std::unique_ptr<McapReader> mcap) : mcap_(std::move(mcap)) {
        for (const McapChannel& c : mcap_->channels())
            if (std::none_of(topics_.begin(), topics_.end(),
                             [&](const Topic& t) { return t.name == c.topic; })) {
                topics_.push_back({c.topic, ros1TypeName(c)});
                channelOf_.push_back(c.id);
            }
    }

    std::string formatName() const override { return "MCAP"; }
    std::vector<std::string> warnings() const override { return mcap_->warnings(); }
    const std::vector<Topic>& topics() const override { return topics_; }
    Expected<std::size_t> indexTopic(const std::string& topic) override {
        const auto channel = channelOf(topic);
        if (!channel)
            return Error{"no topic " + topic};
        handles_.push_back(*channel);
        return handles_.size() - 1;
    }
    std::size_t messageCount(std::size_t handle) const override {
        return mcap_->messageCount(handles_[handle]);
    }
    std::int64_t recordedNs(std::size_t handle, std::size_t i) const override {
        return mcap_->logTimeNs(handles_[handle], i);
    }
    Expected<RosImage> image(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle], i, decodeImage);
    }
    Expected<std::int64_t> imageStampNs(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle], i, decodeHeaderStampNs);
    }
    std::optional<RosImage> firstImage(const std::string& topic) const override {
        return first(topic, decodeImage);
    }
    std::optional<RosCameraInfo> firstCameraInfo(const std::string& topic) const override {
        return first(topic, decodeCameraInfo);
    }

private:
    std::optional<std::uint16_t> channelOf(const std::string& topic) const {
        for (std::size_t i = 0; i < topics_.size(); ++i)
            if (topics_[i].name == topic)
                return channelOf_[i];
        return std::nullopt;
    }
    std::string topicOf(std::uint16_t channel) const {
        for (std::size_t i = 0; i < topics_.size(); ++i)
            if (channelOf_[i] == channel)
                return topics_[i].name;
        return "channel " + std::to_string(channel);
    }
    template <class Value> using Decoder = Expected<Value> (*)(std::span<const std::uint8_t>);

    template <class Value>
    Expected<Value> decoded(std::uint16_t channel, std::size_t i, Decoder<Value> decode) const {
        auto bytes = mcap_->message(channel, i);
        if (!bytes)
            return bytes.error();
        auto value = decode(*bytes);
        if (!value)
            return Error{"message " + std::to_string(i) + " on " + topicOf(channel) + ": " +
                         value.error().message};
        return value;
    }
    // A damaged first message is as good as none: the caller falls back to defaults and says so.
    template <class Value> std::optional<Value> first(const std::string& topic, Decoder<Value> decode) const {
        const auto channel = channelOf(topic);
        if (!channel || mcap_->messageCount(*channel) == 0)
            return std::nullopt;
        auto value = decoded(*channel, 0, decode);
        return value ? std::optional<Value>(std::move(*value)) : std::nullopt;
    }

    std::unique_ptr<McapReader> mcap_;
    std::vector<Topic> topics_;
    std::vector<std::uint16_t> channelOf_; // per topic
    std::vector<std::uint16_t> handles_;   // channel per indexed topic
};

// The value of a top-level or nested "key: value" line of metadata.yaml (rosbag2 writes one per line).
std::vector<std::string> yamlValues(std::istream& in, const std::string& key) {
    std::vector<std::string> values;
    for (std::string line; std::getline(in, line);) {
        const auto at = line.find(key + ":");
        if (at == std::string::npos || line.find_first_not_of(' ') != at)
            continue;
        std::string value = line.substr(at + key.size() + 1);
        value.erase(0, value.find_first_not_of(" \"'"));
        value.erase(value.find_last_not_of(" \"'\r") + 1);
        values.push_back(value);
    }
    return values;
}

} // namespace

Expected<std::string> rosbag2File(const std::string& directory) {
    namespace fs = std::filesystem;
    const fs::path metadata = fs::path(directory) / "metadata.yaml";
    std::ifstream in(metadata);
    if (!in)
        return Error{directory + ": no metadata.yaml (not a rosbag2 folder)"};
    const auto storage = yamlValues(in, "storage_identifier");
    const std::string kind = storage.empty() ? "" : storage.front();
    const std::string extension = kind == "mcap" ? ".mcap" : kind == "sqlite3" ? ".db3" : "";
    if (extension.empty())
        return Error{directory + ": a rosbag2 folder stored as '" + kind +
                     "'; only MCAP and sqlite3 storage are supported"};
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(directory, ec))
        if (entry.path().extension() == extension)
            files.push_back(entry.path());
    if (files.size() != 1)
        return Error{directory + ": " + std::to_string(files.size()) + " " + extension +
                     " files; a rosbag2 folder split over several files is not supported yet"};
    return files.front().string();
}

Expected<std::unique_ptr<replay::ReplaySource>> openMcapSource(const std::string& path,
                                                               const BagOptions& options) {
    std::string file = path;
    if (std::filesystem::is_directory(path)) {
        auto inFolder = rosbag2File(path);
        if (!inFolder)
            return inFolder.error();
        file = *inFolder;
    }
    if (std::filesystem::path(file).extension() == ".db3") {
        auto db3 = openDb3Store(file);
        if (!db3)
            return db3.error();
        return openMessageSource(std::move(*db3), file, options);
    }
    auto mcap = McapReader::open(file);
    if (!mcap)
        return mcap.error();
    return openMessageSource(std::make_unique<McapStore>(std::move(*mcap)), file, options);
}

} // namespace dc::devices::ros
