#include "devices/ros/split_store.h"

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

namespace dc::devices::ros {

namespace {

class SplitStore final : public MessageStore {
public:
    explicit SplitStore(std::vector<std::unique_ptr<MessageStore>> parts) : parts_(std::move(parts)) {
        for (const auto& part : parts_)
            for (const Topic& t : part->topics())
                if (std::none_of(topics_.begin(), topics_.end(),
                                 [&](const Topic& o) { return o.name == t.name; }))
                    topics_.push_back(t);
    }

    std::string formatName() const override { return parts_.front()->formatName(); }
    const std::vector<Topic>& topics() const override { return topics_; }
    std::vector<std::string> warnings() const override {
        std::vector<std::string> all;
        for (const auto& part : parts_)
            for (std::string& w : part->warnings())
                all.push_back(std::move(w));
        return all;
    }

    Expected<std::size_t> indexTopic(const std::string& topic) override {
        std::vector<Piece> pieces;
        for (std::size_t p = 0; p < parts_.size(); ++p) {
            const auto& names = parts_[p]->topics();
            if (std::none_of(names.begin(), names.end(), [&](const Topic& t) { return t.name == topic; }))
                continue;
            auto handle = parts_[p]->indexTopic(topic);
            if (!handle)
                return handle.error();
            pieces.push_back({p, *handle, parts_[p]->messageCount(*handle)});
        }
        if (pieces.empty())
            return Error{"no topic " + topic};
        indexed_.push_back(std::move(pieces));
        return indexed_.size() - 1;
    }
    std::size_t messageCount(std::size_t handle) const override {
        std::size_t count = 0;
        for (const Piece& piece : indexed_[handle])
            count += piece.count;
        return count;
    }
    std::int64_t recordedNs(std::size_t handle, std::size_t i) const override {
        const auto [part, local, index] = locate(handle, i);
        return parts_[part]->recordedNs(local, index);
    }
    Expected<RosImage> image(std::size_t handle, std::size_t i) const override {
        const auto [part, local, index] = locate(handle, i);
        return parts_[part]->image(local, index);
    }
    Expected<std::int64_t> imageStampNs(std::size_t handle, std::size_t i) const override {
        const auto [part, local, index] = locate(handle, i);
        return parts_[part]->imageStampNs(local, index);
    }
    bool readsTransforms() const override { return parts_.front()->readsTransforms(); }
    Expected<std::vector<RosTransformStamped>> transforms(std::size_t handle, std::size_t i) const override {
        const auto [part, local, index] = locate(handle, i);
        return parts_[part]->transforms(local, index);
    }

    std::optional<RosImage> firstImage(const std::string& topic) const override {
        return first<RosImage>([&](const MessageStore& s) { return s.firstImage(topic); });
    }
    std::optional<RosCameraInfo> firstCameraInfo(const std::string& topic) const override {
        return first<RosCameraInfo>([&](const MessageStore& s) { return s.firstCameraInfo(topic); });
    }
    std::optional<float> firstFloat32(const std::string& topic) const override {
        return first<float>([&](const MessageStore& s) { return s.firstFloat32(topic); });
    }
    std::optional<RosTransform> firstTransform(const std::string& topic) const override {
        return first<RosTransform>([&](const MessageStore& s) { return s.firstTransform(topic); });
    }

private:
    // One file's share of an indexed topic: the file, its handle there and its message count.
    struct Piece {
        std::size_t part = 0;
        std::size_t handle = 0;
        std::size_t count = 0;
    };
    struct Location {
        std::size_t part;
        std::size_t handle;
        std::size_t index;
    };

    // Message i of the whole topic as a message of one file (i < messageCount(handle)).
    Location locate(std::size_t handle, std::size_t i) const {
        const std::vector<Piece>& pieces = indexed_[handle];
        for (const Piece& piece : pieces) {
            if (i < piece.count)
                return {piece.part, piece.handle, i};
            i -= piece.count;
        }
        const Piece& last = pieces.back();
        return {last.part, last.handle, last.count};
    }
    // The first file's answer that has one: a topic may begin in a later file.
    template <class Value, class Read> std::optional<Value> first(Read&& read) const {
        for (const auto& part : parts_)
            if (std::optional<Value> value = read(*part))
                return value;
        return std::nullopt;
    }

    std::vector<std::unique_ptr<MessageStore>> parts_;
    std::vector<Topic> topics_;
    std::vector<std::vector<Piece>> indexed_;
};

} // namespace

std::unique_ptr<MessageStore> concatenateStores(std::vector<std::unique_ptr<MessageStore>> parts) {
    if (parts.size() == 1)
        return std::move(parts.front());
    return std::make_unique<SplitStore>(std::move(parts));
}

} // namespace dc::devices::ros
