#include "devices/ros/mcap_source.h"

#include "devices/ros/cdr.h"
#include "devices/ros/db3_store.h"
#include "devices/ros/mcap_reader.h"
#include "devices/ros/message_store.h"
#include "devices/ros/split_store.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

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
        decoders_.push_back(imageDecoderFor(typeOf(topic)));
        return handles_.size() - 1;
    }
    std::size_t messageCount(std::size_t handle) const override {
        return mcap_->messageCount(handles_[handle]);
    }
    std::int64_t recordedNs(std::size_t handle, std::size_t i) const override {
        return mcap_->logTimeNs(handles_[handle], i);
    }
    Expected<RosImage> image(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle], i, decoders_[handle]);
    }
    Expected<std::int64_t> imageStampNs(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle], i, decodeHeaderStampNs);
    }
    bool readsTransforms() const override { return true; }
    Expected<std::vector<RosTransformStamped>> transforms(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle], i, decodeTfMessage);
    }
    std::optional<RosImage> firstImage(const std::string& topic) const override {
        return first(topic, imageDecoderFor(typeOf(topic)));
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
    std::vector<ImageDecoder> decoders_;   // per indexed topic, by its type
};

// One file of a ROS 2 recording: sqlite3 (by its header or its .db3 name) or MCAP.
Expected<std::unique_ptr<MessageStore>> openStore(const std::string& file) {
    if (replay::classifyCapture(file) == replay::CaptureKind::Rosbag2)
        return openDb3Store(file);
    auto mcap = McapReader::open(file);
    if (!mcap)
        return mcap.error();
    return std::unique_ptr<MessageStore>(std::make_unique<McapStore>(std::move(*mcap)));
}

// The files metadata.yaml lists, or every file of the storage's extension in name order where it lists none.
Expected<std::vector<std::string>> filesOfStorage(const std::filesystem::path& directory,
                                                  const YAML::Node& information,
                                                  const std::string& extension) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    if (const YAML::Node listed = information["relative_file_paths"]; listed && listed.IsSequence()) {
        for (const YAML::Node& name : listed) {
            const fs::path file = directory / name.as<std::string>();
            if (!fs::is_regular_file(file))
                return Error{directory.string() + ": metadata.yaml lists " + name.as<std::string>() +
                             ", which is not there"};
            files.push_back(file.string());
        }
        return files;
    }
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(directory, ec))
        if (entry.path().extension() == extension)
            files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

// A file of a split recording replays alone, as asked, but the person learns where the rest is: the other
// files hold the frames before and after it, and often the static transforms. Empty for any other file.
std::vector<std::string> partOfRecording(const std::string& file) {
    namespace fs = std::filesystem;
    const fs::path folder = fs::path(file).parent_path();
    std::error_code ec;
    if (!fs::exists(folder / "metadata.yaml", ec))
        return {};
    const std::string name = folder.empty() ? std::string(".") : folder.string();
    auto files = rosbag2Files(name);
    if (!files || files->size() < 2)
        return {};
    for (std::size_t i = 0; i < files->size(); ++i)
        if (fs::equivalent((*files)[i], file, ec))
            return {file + " is file " + std::to_string(i + 1) + " of " + std::to_string(files->size()) +
                    " of the recording in " + name + ", which replay:" + name + " plays whole"};
    return {};
}

} // namespace

Expected<std::vector<std::string>> rosbag2Files(const std::string& directory) {
    const std::filesystem::path metadata = std::filesystem::path(directory) / "metadata.yaml";
    YAML::Node information;
    try {
        information = YAML::LoadFile(metadata.string())["rosbag2_bagfile_information"];
    } catch (const YAML::Exception& e) {
        return Error{metadata.string() + ": " + e.what()};
    }
    if (!information || !information.IsMap())
        return Error{metadata.string() + ": no rosbag2_bagfile_information (not a rosbag2 folder)"};
    const YAML::Node storage = information["storage_identifier"];
    const std::string kind = storage && storage.IsScalar() ? storage.as<std::string>() : "";
    const std::string extension = kind == "mcap" ? ".mcap" : kind == "sqlite3" ? ".db3" : "";
    if (extension.empty())
        return Error{directory + ": a rosbag2 folder stored as '" + kind +
                     "'; only MCAP and sqlite3 storage are supported"};
    auto files = filesOfStorage(directory, information, extension);
    if (files && files->empty())
        return Error{directory + ": 0 " + extension + " files"};
    return files;
}

Expected<std::unique_ptr<replay::ReplaySource>> openMcapSource(const std::string& path,
                                                               const BagOptions& options) {
    std::vector<std::string> files{path};
    std::vector<std::string> warnings;
    if (!std::filesystem::is_directory(path)) {
        warnings = partOfRecording(path);
    } else {
        auto inFolder = rosbag2Files(path);
        if (!inFolder)
            return inFolder.error();
        files = std::move(*inFolder);
    }
    std::vector<std::unique_ptr<MessageStore>> stores;
    for (const std::string& file : files) {
        auto store = openStore(file);
        if (!store)
            return store.error();
        stores.push_back(std::move(*store));
    }
    return openMessageSource(concatenateStores(std::move(stores)), files.front(), options,
                             std::move(warnings));
}

} // namespace dc::devices::ros
