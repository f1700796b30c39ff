#include "exporting/mcap_writer.h"

#include "base/files.h"

#include <zstd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

namespace dc::exporting {

namespace {

static_assert(std::endian::native == std::endian::little,
              "MCAP's fields are written as the host stores them");

constexpr std::array<std::uint8_t, 8> kMagic{0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum class Op : std::uint8_t {
    Header = 0x01,
    Footer = 0x02,
    Schema = 0x03,
    Channel = 0x04,
    Message = 0x05,
    Chunk = 0x06,
    MessageIndex = 0x07,
    ChunkIndex = 0x08,
    Statistics = 0x0b,
    SummaryOffset = 0x0e,
    DataEnd = 0x0f,
};

// Little-endian fields appended to a byte vector: integers as they are, strings and byte arrays behind
// their uint32 length, records as opcode, uint64 length of the body, body.
class Out {
public:
    explicit Out(std::vector<std::uint8_t>& bytes) : bytes_(bytes) {}

    template <class T> Out& put(T value) {
        const std::size_t at = bytes_.size();
        bytes_.resize(at + sizeof(T));
        std::memcpy(bytes_.data() + at, &value, sizeof(T));
        return *this;
    }
    Out& string(const std::string& s) {
        put(static_cast<std::uint32_t>(s.size()));
        bytes_.insert(bytes_.end(), s.begin(), s.end());
        return *this;
    }
    Out& raw(std::span<const std::uint8_t> data) {
        bytes_.insert(bytes_.end(), data.begin(), data.end());
        return *this;
    }
    // Starts a record or a length-prefixed array, whose length end() fills in once its body is written.
    std::size_t beginRecord(Op op) {
        put(static_cast<std::uint8_t>(op));
        return beginLength<std::uint64_t>();
    }
    template <class L> std::size_t beginLength() {
        put(L{0});
        return bytes_.size();
    }
    template <class L> void end(std::size_t bodyStart) {
        const auto length = static_cast<L>(bytes_.size() - bodyStart);
        std::memcpy(bytes_.data() + bodyStart - sizeof(L), &length, sizeof(L));
    }
    void endRecord(std::size_t bodyStart) { end<std::uint64_t>(bodyStart); }

private:
    std::vector<std::uint8_t>& bytes_;
};

constexpr std::array<std::uint32_t, 256> kCrcTable = [] {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t i = 0; i < 256; ++i) {
        std::uint32_t c = i;
        for (int k = 0; k < 8; ++k)
            c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        table[i] = c;
    }
    return table;
}();

} // namespace

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
    crc = ~crc;
    for (const std::uint8_t b : bytes)
        crc = kCrcTable[(crc ^ b) & 0xff] ^ (crc >> 8);
    return ~crc;
}

McapWriter::McapWriter(std::string path, std::string temporary, base::UniqueFd file,
                       McapWriterOptions options)
    : path_(std::move(path)), temporary_(std::move(temporary)), file_(std::move(file)), options_(options),
      zstd_(ZSTD_createCCtx(), &ZSTD_freeCCtx) {}

McapWriter::~McapWriter() {
    if (!finished_)
        ::unlink(temporary_.c_str());
}

Expected<std::unique_ptr<McapWriter>> McapWriter::create(const std::string& path, McapWriterOptions options) {
    std::error_code ec;
    if (!options.overwrite && std::filesystem::exists(path, ec))
        return Error{path + " already exists (pass --overwrite to replace it)"};
    std::string temporary = path + ".partial-XXXXXX";
    base::UniqueFd file(::mkostemp(temporary.data(), O_CLOEXEC));
    if (!file.valid())
        return Error{"cannot create a file beside " + path + ": " + std::strerror(errno)};
    // mkostemp makes the file private (0600); an export is a file to share, like a recording (0644).
    if (::fchmod(file.get(), 0644) != 0)
        return Error{"cannot set the permissions of " + temporary + ": " + std::strerror(errno)};
    std::unique_ptr<McapWriter> writer(new McapWriter(path, temporary, std::move(file), options));
    std::vector<std::uint8_t> bytes(kMagic.begin(), kMagic.end());
    Out out(bytes);
    const std::size_t header = out.beginRecord(Op::Header);
    out.string("ros2").string("depthcloud");
    out.endRecord(header);
    if (Status s = writer->append(bytes); !s)
        return s.error();
    return writer;
}

Error McapWriter::error(const std::string& what, int errnoValue) const {
    return Error{"cannot " + what + " " + temporary_ + " (for " + path_ + "): " + std::strerror(errnoValue)};
}

Status McapWriter::append(std::span<const std::uint8_t> bytes) {
    if (const int r = base::writeAll(file_.get(), bytes); r < 0)
        return error("write", -r);
    dataCrc_ = crc32(bytes, dataCrc_); // only Data End's own CRC reads it, before it is written
    offset_ += bytes.size();
    return {};
}

std::uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding,
                                    const std::string& data) {
    const auto id = ++schemaCount_;
    for (auto* records : {&chunk_, &schemaRecords_}) {
        Out out(*records);
        const std::size_t body = out.beginRecord(Op::Schema);
        out.put(id).string(name).string(encoding).string(data);
        out.endRecord(body);
    }
    return id;
}

std::uint16_t McapWriter::addChannel(std::uint16_t schema, const std::string& topic,
                                     const std::string& messageEncoding) {
    const auto id = ++channelCount_;
    for (auto* records : {&chunk_, &channelRecords_}) {
        Out out(*records);
        const std::size_t body = out.beginRecord(Op::Channel);
        out.put(id).put(schema).string(topic).string(messageEncoding);
        out.end<std::uint32_t>(out.beginLength<std::uint32_t>()); // metadata: an empty map
        out.endRecord(body);
    }
    return id;
}

Status McapWriter::write(std::uint16_t channel, std::uint64_t logTimeNs, std::span<const std::uint8_t> data) {
    if (chunkIndex_.empty())
        chunkStartNs_ = chunkEndNs_ = logTimeNs;
    chunkStartNs_ = std::min(chunkStartNs_, logTimeNs);
    chunkEndNs_ = std::max(chunkEndNs_, logTimeNs);
    startNs_ = messageCount_ == 0 ? logTimeNs : std::min(startNs_, logTimeNs);
    endNs_ = std::max(endNs_, logTimeNs);
    chunkIndex_[channel].emplace_back(logTimeNs, chunk_.size());
    Out out(chunk_);
    const std::size_t body = out.beginRecord(Op::Message);
    out.put(channel).put(sequences_[channel]++).put(logTimeNs).put(logTimeNs).raw(data);
    out.endRecord(body);
    ++messageCount_;
    ++channelMessageCounts_[channel];
    return chunk_.size() >= options_.chunkBytes ? flushChunk() : Status{};
}

// One Message Index record per channel of the chunk, the first at file offset `firstOffset`; each
// channel's record offset goes to `offsets` for the Chunk Index.
std::vector<std::uint8_t> McapWriter::messageIndexes(std::uint64_t firstOffset,
                                                     std::map<std::uint16_t, std::uint64_t>& offsets) const {
    std::vector<std::uint8_t> bytes;
    Out out(bytes);
    for (const auto& [channel, entries] : chunkIndex_) {
        offsets[channel] = firstOffset + bytes.size();
        const std::size_t body = out.beginRecord(Op::MessageIndex);
        out.put(channel);
        const std::size_t array = out.beginLength<std::uint32_t>();
        for (const auto& [timeNs, offset] : entries)
            out.put(timeNs).put(offset);
        out.end<std::uint32_t>(array);
        out.endRecord(body);
    }
    return bytes;
}

Status McapWriter::flushChunk() {
    if (chunk_.empty())
        return {};
    std::vector<std::uint8_t> compressed(ZSTD_compressBound(chunk_.size()));
    const std::size_t size = ZSTD_compressCCtx(zstd_.get(), compressed.data(), compressed.size(),
                                               chunk_.data(), chunk_.size(), options_.zstdLevel);
    if (ZSTD_isError(size))
        return Error{"cannot compress a chunk of " + path_ + ": " + ZSTD_getErrorName(size)};
    compressed.resize(size);
    std::vector<std::uint8_t> bytes;
    Out out(bytes);
    const std::size_t body = out.beginRecord(Op::Chunk);
    out.put(chunkStartNs_).put(chunkEndNs_).put(static_cast<std::uint64_t>(chunk_.size()));
    out.put(crc32(chunk_)).string("zstd").put(static_cast<std::uint64_t>(size)).raw(compressed);
    out.endRecord(body);
    const std::uint64_t chunkOffset = offset_, chunkLength = bytes.size();
    std::map<std::uint16_t, std::uint64_t> indexOffsets;
    const auto indexes = messageIndexes(chunkOffset + chunkLength, indexOffsets);
    bytes.insert(bytes.end(), indexes.begin(), indexes.end());

    Out index(chunkIndexRecords_);
    const std::size_t indexBody = index.beginRecord(Op::ChunkIndex);
    index.put(chunkStartNs_).put(chunkEndNs_).put(chunkOffset).put(chunkLength);
    const std::size_t map = index.beginLength<std::uint32_t>();
    for (const auto& [channel, offset] : indexOffsets)
        index.put(channel).put(offset);
    index.end<std::uint32_t>(map);
    index.put(static_cast<std::uint64_t>(indexes.size())).string("zstd");
    index.put(static_cast<std::uint64_t>(size)).put(static_cast<std::uint64_t>(chunk_.size()));
    index.endRecord(indexBody);

    chunk_.clear();
    chunkIndex_.clear();
    ++chunkCount_;
    return append(bytes);
}

// The summary section from `summaryStart`: each group of records, and in `offsets` the Summary Offset
// record that points at each group.
std::vector<std::uint8_t> McapWriter::summary(std::uint64_t summaryStart,
                                              std::vector<std::uint8_t>& offsets) const {
    std::vector<std::uint8_t> bytes(schemaRecords_);
    bytes.insert(bytes.end(), channelRecords_.begin(), channelRecords_.end());
    Out out(bytes);
    const std::size_t statistics = out.beginRecord(Op::Statistics);
    out.put(messageCount_).put(schemaCount_).put(static_cast<std::uint32_t>(channelCount_));
    out.put(std::uint32_t{0}).put(std::uint32_t{0}).put(chunkCount_); // attachments, metadata, chunks
    out.put(startNs_).put(endNs_);
    const std::size_t counts = out.beginLength<std::uint32_t>();
    for (const auto& [channel, count] : channelMessageCounts_)
        out.put(channel).put(count);
    out.end<std::uint32_t>(counts);
    out.endRecord(statistics);
    const std::size_t statisticsEnd = bytes.size();
    bytes.insert(bytes.end(), chunkIndexRecords_.begin(), chunkIndexRecords_.end());

    const std::array<std::pair<Op, std::pair<std::size_t, std::size_t>>, 4> groups{{
        {Op::Schema, {0, schemaRecords_.size()}},
        {Op::Channel, {schemaRecords_.size(), schemaRecords_.size() + channelRecords_.size()}},
        {Op::Statistics, {schemaRecords_.size() + channelRecords_.size(), statisticsEnd}},
        {Op::ChunkIndex, {statisticsEnd, bytes.size()}},
    }};
    Out offsetOut(offsets);
    for (const auto& [op, span] : groups) {
        if (span.first == span.second)
            continue;
        const std::size_t body = offsetOut.beginRecord(Op::SummaryOffset);
        offsetOut.put(static_cast<std::uint8_t>(op)).put(summaryStart + span.first);
        offsetOut.put(static_cast<std::uint64_t>(span.second - span.first));
        offsetOut.endRecord(body);
    }
    return bytes;
}

Status McapWriter::finish() {
    if (Status s = flushChunk(); !s)
        return s;
    std::vector<std::uint8_t> bytes;
    Out out(bytes);
    const std::size_t dataEnd = out.beginRecord(Op::DataEnd);
    out.put(dataCrc_);
    out.endRecord(dataEnd);
    const std::uint64_t summaryStart = offset_ + bytes.size();
    std::vector<std::uint8_t> offsets;
    const auto summaryBytes = summary(summaryStart, offsets);
    bytes.insert(bytes.end(), summaryBytes.begin(), summaryBytes.end());
    const std::uint64_t summaryOffsetStart = offset_ + bytes.size();
    bytes.insert(bytes.end(), offsets.begin(), offsets.end());
    // The summary CRC covers the summary, the summary offsets and the footer up to the CRC itself, its
    // length included, so the length is written as it will be rather than patched afterwards.
    out.put(static_cast<std::uint8_t>(Op::Footer)).put(std::uint64_t{8 + 8 + 4});
    out.put(summaryStart).put(summaryOffsetStart);
    const std::size_t summaryAt = static_cast<std::size_t>(summaryStart - offset_);
    out.put(crc32(std::span(bytes).subspan(summaryAt)));
    out.raw(kMagic);
    if (Status s = append(bytes); !s)
        return s;
    if (::fsync(file_.get()) != 0)
        return error("flush", errno);
    file_.reset();
    if (Status s =
            base::renameInto(temporary_, path_, options_.overwrite,
                             path_ + " appeared while it was written (pass --overwrite to replace it)");
        !s)
        return s;
    finished_ = true;
    return {};
}

} // namespace dc::exporting
