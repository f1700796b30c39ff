#include "devices/ros/mcap_reader.h"

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <optional>

namespace dc::devices::ros {

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::size_t kRecordHeaderBytes = 9; // opcode, u64 length
constexpr std::size_t kFooterBytes = kRecordHeaderBytes + 20;
// A chunk that claims more than this is damaged (writers chunk at a few MiB): refusing it keeps a corrupt
// length from allocating the machine's memory.
constexpr std::uint64_t kMaxChunkBytes = 1ull << 30;

enum Opcode : std::uint8_t {
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kMessageIndex = 0x07,
    kChunkIndex = 0x08,
    kDataEnd = 0x0f,
};

// Little-endian fields of one record, bounds-checked: a read past the end sets failed() and yields zeros.
class Cursor {
public:
    explicit Cursor(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

    template <class T> T read() {
        T v{};
        if (!take(sizeof(T)))
            return v;
        std::memcpy(&v, bytes_.data() + pos_ - sizeof(T), sizeof(T)); // MCAP is little-endian, as we are
        return v;
    }
    std::span<const std::uint8_t> bytes(std::uint64_t n) {
        if (!take(n))
            return {};
        return bytes_.subspan(pos_ - n, n);
    }
    std::string string() {
        const auto b = bytes(read<std::uint32_t>());
        return {b.begin(), b.end()};
    }
    std::span<const std::uint8_t> rest() { return bytes(bytes_.size() - pos_); }
    bool failed() const { return failed_; }

private:
    bool take(std::uint64_t n) {
        if (failed_ || n > bytes_.size() - pos_) {
            failed_ = true;
            return false;
        }
        pos_ += n;
        return true;
    }
    std::span<const std::uint8_t> bytes_;
    std::size_t pos_ = 0;
    bool failed_ = false;
};

struct Record {
    std::uint8_t opcode = 0;
    std::span<const std::uint8_t> body;
};

// The record at `offset` of `bytes`, or nothing when its header or body runs past the end.
std::optional<Record> recordAt(std::span<const std::uint8_t> bytes, std::uint64_t offset) {
    if (offset > bytes.size() || bytes.size() - offset < kRecordHeaderBytes)
        return std::nullopt;
    Cursor c(bytes.subspan(offset));
    const auto opcode = c.read<std::uint8_t>();
    const auto length = c.read<std::uint64_t>();
    if (length > bytes.size() - offset - kRecordHeaderBytes)
        return std::nullopt;
    return Record{opcode, bytes.subspan(offset + kRecordHeaderBytes, length)};
}

Status decompressLz4(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out) {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
        return Error{"lz4: no decompression context"};
    const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
        raw, &LZ4F_freeDecompressionContext);
    std::size_t inPos = 0, outPos = 0;
    while (inPos < in.size()) {
        std::size_t inLeft = in.size() - inPos, outLeft = out.size() - outPos;
        const std::size_t hint =
            LZ4F_decompress(ctx.get(), out.data() + outPos, &outLeft, in.data() + inPos, &inLeft, nullptr);
        if (LZ4F_isError(hint))
            return Error{std::string("lz4: ") + LZ4F_getErrorName(hint)};
        inPos += inLeft;
        outPos += outLeft;
        if (hint == 0)
            break; // end of frame
        if (inLeft == 0 && outLeft == 0)
            return Error{"lz4: the data ends inside its frame"};
    }
    if (outPos != out.size())
        return Error{"lz4: " + std::to_string(outPos) + " bytes decompressed, the chunk says " +
                     std::to_string(out.size())};
    return {};
}

std::optional<McapReader::ChunkIndex> parseChunkIndex(std::span<const std::uint8_t> body) {
    Cursor c(body);
    c.bytes(16); // message start and end time
    McapReader::ChunkIndex index;
    index.chunkOffset = c.read<std::uint64_t>();
    c.read<std::uint64_t>(); // chunk length
    const auto map = c.bytes(c.read<std::uint32_t>());
    if (c.failed() || map.size() % 10 != 0) // entries of u16 channel, u64 offset
        return std::nullopt;
    Cursor entries(map);
    for (std::size_t i = 0; i < map.size() / 10; ++i) {
        entries.read<std::uint16_t>();
        index.messageIndexOffsets.push_back(entries.read<std::uint64_t>());
    }
    return index;
}

} // namespace

Status decompressChunk(std::span<const std::uint8_t> compressed, const std::string& compression,
                       std::uint64_t uncompressedSize, std::vector<std::uint8_t>& out) {
    if (uncompressedSize > kMaxChunkBytes)
        return Error{"a chunk of " + std::to_string(uncompressedSize) + " bytes is more than a chunk can be"};
    // Sizes the data cannot decompress to are refused before the buffer is made: LZ4 expands at most
    // 255-fold, and a zstd frame that records its size must agree.
    const std::uint64_t zstdSize = compression == "zstd"
                                       ? ZSTD_getFrameContentSize(compressed.data(), compressed.size())
                                       : ZSTD_CONTENTSIZE_UNKNOWN;
    if ((compression == "lz4" && uncompressedSize > 255 * compressed.size() + 64) ||
        (zstdSize != ZSTD_CONTENTSIZE_UNKNOWN && zstdSize != uncompressedSize))
        return Error{"a " + compression + " chunk of " + std::to_string(compressed.size()) +
                     " bytes cannot hold the " + std::to_string(uncompressedSize) + " it claims"};
    out.resize(uncompressedSize);
    if (compression.empty()) {
        if (compressed.size() != uncompressedSize)
            return Error{"an uncompressed chunk's sizes differ"};
        std::copy(compressed.begin(), compressed.end(), out.begin());
        return {};
    }
    if (compression == "lz4")
        return decompressLz4(compressed, out);
    if (compression != "zstd")
        return Error{"chunks compressed with '" + compression + "' are not supported (zstd, lz4 are)"};
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
    if (ZSTD_isError(n))
        return Error{std::string("zstd: ") + ZSTD_getErrorName(n)};
    if (n != uncompressedSize)
        return Error{"zstd: " + std::to_string(n) + " bytes decompressed, the chunk says " +
                     std::to_string(uncompressedSize)};
    return {};
}

Error McapReader::error(std::uint64_t offset, const std::string& what) const {
    return Error{path_ + ": at byte " + std::to_string(offset) + ": " + what};
}

Expected<std::unique_ptr<McapReader>> McapReader::open(const std::string& path) {
    auto map = base::mapFile(path);
    if (!map)
        return map.error();
    const auto bytes = map->bytes();
    auto reader = fromBytes(bytes, path);
    if (reader)
        (*reader)->map_ = std::move(*map);
    return reader;
}

Expected<std::unique_ptr<McapReader>> McapReader::fromBytes(std::span<const std::uint8_t> bytes,
                                                            const std::string& name) {
    std::unique_ptr<McapReader> reader(new McapReader(name));
    reader->file_ = bytes;
    if (bytes.size() < sizeof kMagic || !std::equal(kMagic, kMagic + sizeof kMagic, bytes.begin()))
        return Error{name + " is not an MCAP file (it does not start with MCAP's magic bytes)"};
    bool summary = false;
    if (Status s = reader->readSummary(summary); !s) {
        // An index that contradicts the file is no reason to give up on the data itself.
        reader->warnings_.push_back(s.error().message + "; read by a pass over the data instead");
        reader->messages_.clear();
        reader->chunks_.clear();
        reader->cachedChunk_ = kNoChunk;
        summary = false;
    }
    if (!summary)
        reader->scanDataSection();
    reader->fromSummary_ = summary;
    for (auto& [channel, refs] : reader->messages_)
        std::stable_sort(refs.begin(), refs.end(),
                         [](const MessageRef& a, const MessageRef& b) { return a.logTimeNs < b.logTimeNs; });
    return reader;
}

std::size_t McapReader::messageCount(std::uint16_t channel) const {
    const auto found = messages_.find(channel);
    return found == messages_.end() ? 0 : found->second.size();
}

std::int64_t McapReader::logTimeNs(std::uint16_t channel, std::size_t i) const {
    return messages_.at(channel)[i].logTimeNs;
}

void McapReader::addSchema(std::span<const std::uint8_t> body) {
    Cursor c(body);
    const auto id = c.read<std::uint16_t>();
    std::string name = c.string();
    if (!c.failed() && id != 0) // schema 0 means "no schema"
        schemaNames_[id] = std::move(name);
}

void McapReader::addChannel(std::span<const std::uint8_t> body) {
    Cursor c(body);
    McapChannel channel;
    channel.id = c.read<std::uint16_t>();
    const auto schema = c.read<std::uint16_t>();
    channel.topic = c.string();
    channel.messageEncoding = c.string();
    if (c.failed() || std::any_of(channels_.begin(), channels_.end(),
                                  [&](const McapChannel& k) { return k.id == channel.id; }))
        return; // the summary repeats the data section's channels
    if (const auto found = schemaNames_.find(schema); found != schemaNames_.end())
        channel.schemaName = found->second;
    channels_.push_back(std::move(channel));
}

void McapReader::note(std::uint8_t opcode, std::span<const std::uint8_t> body, std::uint32_t chunk,
                      std::uint64_t offset) {
    if (opcode == kSchema)
        addSchema(body);
    else if (opcode == kChannel)
        addChannel(body);
    if (opcode != kMessage)
        return;
    Cursor c(body);
    const auto channel = c.read<std::uint16_t>();
    c.read<std::uint32_t>(); // sequence
    const auto logTime = c.read<std::uint64_t>();
    if (!c.failed())
        messages_[channel].push_back({static_cast<std::int64_t>(logTime), chunk, offset});
}

Status McapReader::scanRecords(std::span<const std::uint8_t> records, std::uint32_t chunk) {
    for (std::uint64_t offset = 0; offset < records.size();) {
        const auto record = recordAt(records, offset);
        if (!record)
            return Error{"a record at byte " + std::to_string(offset) + " of chunk " + std::to_string(chunk) +
                         " runs past the chunk's end"};
        note(record->opcode, record->body, chunk, offset);
        offset += kRecordHeaderBytes + record->body.size();
    }
    return {};
}

Status McapReader::indexChunk(std::uint64_t chunkRecordOffset, bool scanRecords) {
    const auto record = recordAt(file_, chunkRecordOffset);
    if (!record || record->opcode != kChunk)
        return error(chunkRecordOffset, "no chunk where the index points");
    Cursor c(record->body);
    c.read<std::uint64_t>(); // message start time
    c.read<std::uint64_t>(); // message end time
    Chunk chunk;
    chunk.uncompressedSize = c.read<std::uint64_t>();
    c.read<std::uint32_t>(); // CRC of the records: zstd and lz4 frames check their own data
    chunk.compression = c.string();
    const auto records = c.bytes(c.read<std::uint64_t>());
    if (c.failed())
        return error(chunkRecordOffset, "a chunk's header is damaged");
    chunk.recordsOffset = static_cast<std::uint64_t>(records.data() - file_.data());
    chunk.compressedSize = records.size();
    chunks_.push_back(std::move(chunk));
    const auto index = static_cast<std::uint32_t>(chunks_.size() - 1);
    if (!scanRecords)
        return {};
    auto decompressed = chunkRecords(index);
    if (!decompressed)
        return error(chunkRecordOffset, decompressed.error().message);
    if (Status s = this->scanRecords(*decompressed, index); !s)
        return error(chunkRecordOffset, s.error().message);
    return {};
}

Status McapReader::readMessageIndex(std::uint64_t offset, std::uint32_t chunk) {
    const auto record = recordAt(file_, offset);
    if (!record || record->opcode != kMessageIndex)
        return error(offset, "no message index where the chunk index points");
    Cursor c(record->body);
    const auto channel = c.read<std::uint16_t>();
    const auto entries = c.bytes(c.read<std::uint32_t>());
    if (c.failed() || entries.size() % 16 != 0)
        return error(offset, "a message index is damaged");
    Cursor e(entries);
    auto& refs = messages_[channel];
    for (std::size_t i = 0; i < entries.size() / 16; ++i) {
        const auto logTime = e.read<std::uint64_t>();
        refs.push_back({static_cast<std::int64_t>(logTime), chunk, e.read<std::uint64_t>()});
    }
    return {};
}

// The chunk indexes the summary lists, each with its message indexes; `found` is false for a file without
// a summary or without chunk indexes in it (an unchunked file), which the data pass then reads.
Status McapReader::readSummary(bool& found) {
    found = false;
    const std::size_t size = file_.size();
    if (size < 2 * sizeof kMagic + kFooterBytes ||
        !std::equal(kMagic, kMagic + sizeof kMagic, file_.end() - sizeof kMagic))
        return {};
    const std::uint64_t footerOffset = size - sizeof kMagic - kFooterBytes;
    const auto footer = recordAt(file_.first(size - sizeof kMagic), footerOffset);
    if (!footer || footer->opcode != kFooter)
        return {};
    Cursor f(footer->body);
    const auto summaryStart = f.read<std::uint64_t>();
    const auto summaryOffsetStart = f.read<std::uint64_t>();
    if (summaryStart == 0)
        return {};
    const std::uint64_t end = summaryOffsetStart != 0 ? summaryOffsetStart : footerOffset;
    if (summaryStart > end || end > footerOffset)
        return error(footerOffset, "the footer points outside the file");
    std::vector<ChunkIndex> chunkIndexes;
    for (std::uint64_t offset = summaryStart; offset < end;) {
        const auto record = recordAt(file_.first(end), offset);
        if (!record)
            return error(offset, "a summary record runs past the summary");
        if (record->opcode == kSchema || record->opcode == kChannel)
            note(record->opcode, record->body, kNoChunk, offset);
        if (record->opcode == kChunkIndex) {
            auto index = parseChunkIndex(record->body);
            if (!index)
                return error(offset, "a chunk index is damaged");
            chunkIndexes.push_back(std::move(*index));
        }
        offset += kRecordHeaderBytes + record->body.size();
    }
    if (chunkIndexes.empty())
        return {};
    for (const ChunkIndex& index : chunkIndexes)
        if (Status s = indexChunk(index); !s)
            return s;
    found = true;
    return {};
}

// One chunk from its index: its message indexes, or its records where the writer left those out.
Status McapReader::indexChunk(const ChunkIndex& index) {
    if (Status s = indexChunk(index.chunkOffset, index.messageIndexOffsets.empty()); !s)
        return s;
    const auto chunk = static_cast<std::uint32_t>(chunks_.size() - 1);
    for (std::uint64_t offset : index.messageIndexOffsets)
        if (Status s = readMessageIndex(offset, chunk); !s)
            return s;
    return {};
}

// Every record from the header on, in file order; a record cut by the end of the file (or a chunk that
// does not decompress) ends the pass with a warning, keeping what came before.
void McapReader::scanDataSection() {
    std::uint64_t offset = sizeof kMagic;
    while (offset < file_.size()) {
        const auto record = recordAt(file_, offset);
        if (!record) {
            warnings_.push_back(path_ + ": cut short at byte " + std::to_string(offset) + " of " +
                                std::to_string(file_.size()) + "; replaying what was recorded before it");
            return;
        }
        if (record->opcode == kDataEnd || record->opcode == kFooter)
            return;
        if (record->opcode == kChunk) {
            if (Status s = indexChunk(offset, true); !s) {
                warnings_.push_back(s.error().message + "; replaying what was recorded before it");
                return;
            }
        } else {
            note(record->opcode, record->body, kNoChunk, offset);
        }
        offset += kRecordHeaderBytes + record->body.size();
    }
}

Expected<std::span<const std::uint8_t>> McapReader::chunkRecords(std::uint32_t chunk) const {
    const Chunk& c = chunks_[chunk];
    const auto compressed = file_.subspan(c.recordsOffset, c.compressedSize);
    if (c.compression.empty() && c.compressedSize == c.uncompressedSize)
        return compressed; // read in place
    if (cachedChunk_ != chunk) {
        cachedChunk_ = kNoChunk;
        if (Status s = decompressChunk(compressed, c.compression, c.uncompressedSize, cache_); !s)
            return s.error();
        cachedChunk_ = chunk;
    }
    return std::span<const std::uint8_t>(cache_);
}

Expected<std::span<const std::uint8_t>> McapReader::message(std::uint16_t channel, std::size_t i) const {
    const MessageRef& ref = messages_.at(channel)[i];
    std::span<const std::uint8_t> records = file_;
    if (ref.chunk != kNoChunk) {
        auto decompressed = chunkRecords(ref.chunk);
        if (!decompressed)
            return error(chunks_[ref.chunk].recordsOffset, decompressed.error().message);
        records = *decompressed;
    }
    const auto record = recordAt(records, ref.offset);
    const std::string where = ref.chunk == kNoChunk ? "" : " of chunk " + std::to_string(ref.chunk);
    if (!record || record->opcode != kMessage)
        return Error{path_ + ": no message at byte " + std::to_string(ref.offset) + where +
                     ", where the index points"};
    Cursor c(record->body);
    const auto recordChannel = c.read<std::uint16_t>();
    c.bytes(20); // sequence, log time, publish time
    const auto data = c.rest();
    if (c.failed() || recordChannel != channel)
        return Error{path_ + ": the message at byte " + std::to_string(ref.offset) + where +
                     " is not the indexed channel's"};
    return data;
}

} // namespace dc::devices::ros
