#pragma once

#include "base/expected.h"
#include "base/unique_fd.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

typedef struct ZSTD_CCtx_s ZSTD_CCtx;

namespace dc::exporting {

struct McapWriterOptions {
    bool overwrite = false; // replace an existing file at the destination
    // Records gathered before a chunk is compressed and written: large enough for zstd to find the
    // redundancy between consecutive frames, small enough that a reader seeking one message decompresses
    // little. A message larger than this makes a chunk of its own.
    std::size_t chunkBytes = 4u << 20;
    int zstdLevel = 3; // zstd's own default: several times smaller than level 1 on depth, still fast
};

// Writes an MCAP file (mcap.dev/spec, version 0) as readers expect to find one: the Header, messages in
// zstd chunks each followed by its Message Index records, Data End with the data section's CRC, then the
// summary (every Schema and Channel, Statistics, a Chunk Index per chunk), the Summary Offset records, the
// Footer with the summary's CRC, and the closing magic. Every chunk carries the CRC of its uncompressed
// records. The file is written beside the destination under a temporary name and renamed onto it only by
// finish(), so a failed or abandoned write never leaves a half file, nor replaces a good one. Messages must
// come in non-decreasing log time for the indexes to be in order. Not thread-safe.
class McapWriter {
public:
    // Creates the temporary file; fails when `path` exists and options.overwrite is false.
    static Expected<std::unique_ptr<McapWriter>> create(const std::string& path,
                                                        McapWriterOptions options = {});
    ~McapWriter(); // removes the temporary file unless finish() succeeded
    McapWriter(const McapWriter&) = delete;
    McapWriter& operator=(const McapWriter&) = delete;

    // Ids count from 1 (schema 0 means "none" in MCAP). The records go into the current chunk, so they
    // precede the first message that uses them, and are repeated in the summary.
    std::uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
    std::uint16_t addChannel(std::uint16_t schema, const std::string& topic,
                             const std::string& messageEncoding);
    // One message; publish time is the log time.
    Status write(std::uint16_t channel, std::uint64_t logTimeNs, std::span<const std::uint8_t> data);
    // Writes the rest of the file and renames it to its destination.
    Status finish();

    std::uint64_t messageCount() const { return messageCount_; }
    std::uint64_t bytesWritten() const { return offset_; }

private:
    McapWriter(std::string path, std::string temporary, base::UniqueFd file, McapWriterOptions options);
    Status append(std::span<const std::uint8_t> bytes);
    Status flushChunk();
    std::vector<std::uint8_t> messageIndexes(std::uint64_t firstOffset,
                                             std::map<std::uint16_t, std::uint64_t>& offsets) const;
    std::vector<std::uint8_t> summary(std::uint64_t summaryStart, std::vector<std::uint8_t>& offsets) const;
    Error error(const std::string& what, int errnoValue) const;

    std::string path_;
    std::string temporary_;
    base::UniqueFd file_;
    McapWriterOptions options_;
    std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> zstd_;
    std::uint64_t offset_ = 0;
    std::uint32_t dataCrc_ = 0; // of every byte written before Data End
    bool finished_ = false;

    std::vector<std::uint8_t> schemaRecords_, channelRecords_, chunkIndexRecords_;
    std::uint16_t schemaCount_ = 0, channelCount_ = 0;

    // The chunk being gathered: its records, time span and each channel's (log time, offset) index.
    std::vector<std::uint8_t> chunk_;
    std::uint64_t chunkStartNs_ = 0, chunkEndNs_ = 0;
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunkIndex_;

    std::uint64_t messageCount_ = 0, startNs_ = 0, endNs_ = 0;
    std::uint32_t chunkCount_ = 0;
    std::map<std::uint16_t, std::uint64_t> channelMessageCounts_;
    std::map<std::uint16_t, std::uint32_t> sequences_;
};

// CRC-32 (ISO-HDLC, zlib's), continued from `crc` (0 to start): MCAP's checksum.
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

} // namespace dc::exporting
