#include "devices/ros/db3_store.h"

#include "devices/ros/cdr.h"

#include <sqlite3.h>

#include <span>
#include <utility>
#include <vector>

namespace dc::devices::ros {

namespace {

using Database = std::unique_ptr<sqlite3, decltype(&sqlite3_close)>;
using Statement = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;

class Db3Store final : public MessageStore {
public:
    Db3Store(std::string path, Database db) : path_(std::move(path)), db_(std::move(db)) {}

    Status readTopics();
    std::string formatName() const override { return "rosbag2 sqlite3"; }
    const std::vector<Topic>& topics() const override { return topics_; }
    Expected<std::size_t> indexTopic(const std::string& topic) override;
    std::size_t messageCount(std::size_t handle) const override { return handles_[handle].size(); }
    std::int64_t recordedNs(std::size_t handle, std::size_t i) const override {
        return handles_[handle][i].second;
    }
    Expected<RosImage> image(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle][i].first, decoders_[handle]);
    }
    bool readsTransforms() const override { return true; }
    Expected<std::vector<RosTransformStamped>> transforms(std::size_t handle, std::size_t i) const override {
        return decoded(handles_[handle][i].first, decodeTfMessage);
    }
    std::optional<RosImage> firstImage(const std::string& topic) const override {
        return first(topic, imageDecoderFor(typeOf(topic)));
    }
    std::optional<RosCameraInfo> firstCameraInfo(const std::string& topic) const override {
        return first(topic, decodeCameraInfo);
    }

private:
    template <class Value> using Decoder = Expected<Value> (*)(std::span<const std::uint8_t>);

    Expected<Statement> prepare(const char* sql) const {
        sqlite3_stmt* statement = nullptr;
        if (sqlite3_prepare_v2(db_.get(), sql, -1, &statement, nullptr) != SQLITE_OK)
            return Error{path_ + ": " + sqlite3_errmsg(db_.get())};
        return Statement(statement, &sqlite3_finalize);
    }
    // One message's bytes by the query's first column, with `id` bound to its parameter.
    Expected<std::vector<std::uint8_t>> blob(const char* sql, std::int64_t id) const {
        auto statement = prepare(sql);
        if (!statement)
            return statement.error();
        sqlite3_bind_int64(statement->get(), 1, id);
        if (sqlite3_step(statement->get()) != SQLITE_ROW)
            return Error{path_ + ": no message " + std::to_string(id)};
        const auto* bytes = static_cast<const std::uint8_t*>(sqlite3_column_blob(statement->get(), 0));
        return std::vector<std::uint8_t>(bytes, bytes + sqlite3_column_bytes(statement->get(), 0));
    }
    template <class Value> Expected<Value> decoded(std::int64_t row, Decoder<Value> decode) const {
        auto bytes = blob("SELECT data FROM messages WHERE id = ?", row);
        if (!bytes)
            return bytes.error();
        auto value = decode(*bytes);
        if (!value)
            return Error{"message " + std::to_string(row) + ": " + value.error().message};
        return value;
    }
    // A damaged first message is as good as none: the caller falls back to defaults and says so.
    template <class Value> std::optional<Value> first(const std::string& topic, Decoder<Value> decode) const {
        const auto id = topicId(topic);
        if (!id)
            return std::nullopt;
        auto bytes = blob("SELECT data FROM messages WHERE topic_id = ? ORDER BY timestamp, id LIMIT 1", *id);
        auto value = bytes ? decode(*bytes) : Expected<Value>(bytes.error());
        return value ? std::optional<Value>(std::move(*value)) : std::nullopt;
    }
    std::optional<std::int64_t> topicId(const std::string& topic) const {
        for (std::size_t i = 0; i < topics_.size(); ++i)
            if (topics_[i].name == topic)
                return topicIds_[i];
        return std::nullopt;
    }

    std::string path_;
    Database db_;
    std::vector<Topic> topics_;
    std::vector<std::int64_t> topicIds_; // per topic
    // Per indexed topic: each message's (row id, receive time), in receive-time order.
    std::vector<std::vector<std::pair<std::int64_t, std::int64_t>>> handles_;
    std::vector<ImageDecoder> decoders_; // per indexed topic, by its type
};

Status Db3Store::readTopics() {
    auto statement = prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    if (!statement)
        return statement.error();
    while (sqlite3_step(statement->get()) == SQLITE_ROW) {
        auto text = [&](int column) {
            const auto* s = sqlite3_column_text(statement->get(), column);
            return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
        };
        // ROS 2 spells its types pkg/msg/Type; the replay matches ROS 1's pkg/Type, and decodes CDR only.
        std::string type = text(2);
        if (const auto at = type.find("/msg/"); at != std::string::npos)
            type.erase(at, 4);
        const std::string format = text(3);
        topics_.push_back({text(1), format == "cdr" ? type : type + " (" + format + ")"});
        topicIds_.push_back(sqlite3_column_int64(statement->get(), 0));
    }
    return {};
}

Expected<std::size_t> Db3Store::indexTopic(const std::string& topic) {
    const auto id = topicId(topic);
    if (!id)
        return Error{"no topic " + topic};
    auto statement = prepare("SELECT id, timestamp FROM messages WHERE topic_id = ? ORDER BY timestamp, id");
    if (!statement)
        return statement.error();
    sqlite3_bind_int64(statement->get(), 1, *id);
    std::vector<std::pair<std::int64_t, std::int64_t>> rows;
    while (sqlite3_step(statement->get()) == SQLITE_ROW)
        rows.emplace_back(sqlite3_column_int64(statement->get(), 0),
                          sqlite3_column_int64(statement->get(), 1));
    handles_.push_back(std::move(rows));
    decoders_.push_back(imageDecoderFor(typeOf(topic)));
    return handles_.size() - 1;
}

} // namespace

Expected<std::unique_ptr<MessageStore>> openDb3Store(const std::string& path) {
    sqlite3* raw = nullptr;
    const int opened = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    Database db(raw, &sqlite3_close);
    if (opened != SQLITE_OK)
        return Error{"cannot open " + path + ": " + (raw ? sqlite3_errmsg(raw) : sqlite3_errstr(opened))};
    auto store = std::make_unique<Db3Store>(path, std::move(db));
    if (Status s = store->readTopics(); !s)
        return Error{s.error().message + " (not a rosbag2 sqlite3 file)"};
    return std::unique_ptr<MessageStore>(std::move(store));
}

} // namespace dc::devices::ros
