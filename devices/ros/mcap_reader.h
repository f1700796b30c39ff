#pragma once

#include "base/expected.h"
#include "base/mapped_file.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dc::devices::ros {

// One channel of an MCAP file: a topic with its message encoding and schema.
struct McapChannel {
    std::uint16_t id = 0;
    std::string topic;
    std::string messageEncoding; // "cdr" for ROS 2
    std::string schemaName;      // "sensor_msgs/msg/Image"
};

// An MCAP file (mcap.dev/spec), mapped, with every message's place indexed on open: from the summary's
// chunk indexes and the message indexes they point at when the file has them, else by one pass over the
// data section, which also recovers a file cut short (no summary, a cut chunk) up to the cut. Chunks may be
// uncompressed, zstd or lz4 (frame format); the last chunk read stays decompressed, so reading a channel in
// order decompresses each chunk once. Not thread-safe.
class McapReader {
public:
    static Expected<std::unique_ptr<McapReader>> open(const std::string& path);
    // The same over bytes in memory that outlive the reader (the fuzzer's); `name` stands for the file.
    static Expected<std::unique_ptr<McapReader>> fromBytes(std::span<const std::uint8_t> bytes,
                                                           const std::string& name);

    const std::vector<McapChannel>& channels() const { return channels_; }
    // A channel's messages, in log-time order (recorded order among equal times).
    std::size_t messageCount(std::uint16_t channel) const;
    std::int64_t logTimeNs(std::uint16_t channel, std::size_t i) const;
    // The serialized message (i < messageCount): valid until the next call. Errors name the file offset.
    Expected<std::span<const std::uint8_t>> message(std::uint16_t channel, std::size_t i) const;
    // Whether the messages were found through the summary's indexes (else by a pass over the data).
    bool readFromSummary() const { return fromSummary_; }
    // What opening recovered from: a truncated or damaged file.
    const std::vector<std::string>& warnings() const { return warnings_; }

    // Where a message record lies: in the data section (chunk == kNoChunk) or in a chunk's decompressed
    // records, at the record's opcode.
    static constexpr std::uint32_t kNoChunk = 0xffffffff;
    struct MessageRef {
        std::int64_t logTimeNs = 0;
        std::uint32_t chunk = kNoChunk;
        std::uint64_t offset = 0;
    };
    struct Chunk {
        std::uint64_t recordsOffset = 0; // in the file
        std::uint64_t compressedSize = 0;
        std::uint64_t uncompressedSize = 0;
        std::string compression; // "", "zstd" or "lz4"
    };

    struct ChunkIndex {
        std::uint64_t chunkOffset = 0;                  // of the chunk record
        std::vector<std::uint64_t> messageIndexOffsets; // of its message index records, one per channel
    };

private:
    explicit McapReader(std::string path) : path_(std::move(path)) {}
    Status readSummary(bool& found);
    Status indexChunk(const ChunkIndex& index);
    Status indexChunk(std::uint64_t chunkRecordOffset, bool scanRecords);
    Status readMessageIndex(std::uint64_t offset, std::uint32_t chunk);
    void scanDataSection();
    Status scanRecords(std::span<const std::uint8_t> records, std::uint32_t chunk);
    Expected<std::span<const std::uint8_t>> chunkRecords(std::uint32_t chunk) const;
    // Registers a schema, channel or message record found at `offset` (of the file or of `chunk`).
    void note(std::uint8_t opcode, std::span<const std::uint8_t> body, std::uint32_t chunk,
              std::uint64_t offset);
    void addSchema(std::span<const std::uint8_t> body);
    void addChannel(std::span<const std::uint8_t> body);
    Error error(std::uint64_t offset, const std::string& what) const;

    std::string path_;
    base::MappedRegion map_;
    std::span<const std::uint8_t> file_;
    std::map<std::uint16_t, std::string> schemaNames_;
    std::vector<McapChannel> channels_;
    std::map<std::uint16_t, std::vector<MessageRef>> messages_;
    std::vector<Chunk> chunks_;
    std::vector<std::string> warnings_;
    bool fromSummary_ = false;
    mutable std::uint32_t cachedChunk_ = kNoChunk;
    mutable std::vector<std::uint8_t> cache_;
};

// A chunk's records decompressed into `out` (exactly uncompressedSize bytes).
Status decompressChunk(std::span<const std::uint8_t> compressed, const std::string& compression,
                       std::uint64_t uncompressedSize, std::vector<std::uint8_t>& out);

} // namespace dc::devices::ros
