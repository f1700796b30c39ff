#include "devices/recording/format.h"

#include "devices/recording/byte_io.h"

#include <algorithm>
#include <xxhash.h>

namespace dc::devices::recording {

std::uint32_t checksumOf(std::span<const std::uint8_t> bytes) {
    return static_cast<std::uint32_t>(XXH3_64bits(bytes.data(), bytes.size()));
}

bool checksumMatches(std::uint32_t stored, std::uint32_t computed) {
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
    (void)stored;
    (void)computed;
    return true;
#else
    return stored == computed;
#endif
}

std::vector<std::uint8_t> encodeFileHeader(const FileHeader& header) {
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.putBytes(kFileMagic);
    w.put(header.versionMajor);
    w.put(header.versionMinor);
    w.put(static_cast<std::uint32_t>(kFileHeaderSize));
    w.put(header.createdUnixNs);
    w.put(std::uint32_t{0}); // flags, none defined in version 1
    w.put(checksumOf(out));
    return out;
}

Expected<FileHeader> decodeFileHeader(std::span<const std::uint8_t> bytes, const std::string& file) {
    if (bytes.size() < kFileHeaderSize)
        return Error{file + ": truncated file: " + std::to_string(bytes.size()) +
                     " bytes, the header alone needs " + std::to_string(kFileHeaderSize) + " (byte offset " +
                     std::to_string(bytes.size()) + ")"};
    if (!std::equal(kFileMagic.begin(), kFileMagic.end(), bytes.begin()))
        return Error{file + ": not a depthcloud recording (wrong magic at byte offset 0)"};
    ByteReader r(bytes.first(kFileHeaderSize), 0);
    (void)r.getBytes(kFileMagic.size());
    FileHeader h;
    h.versionMajor = r.get<std::uint16_t>();
    h.versionMinor = r.get<std::uint16_t>();
    // The version is checked before the checksum: a future version may lay its header out differently.
    if (h.versionMajor > kVersionMajor)
        return Error{file + ": written by a newer depthcloud (format version " +
                     std::to_string(h.versionMajor) + "." + std::to_string(h.versionMinor) +
                     "); this build reads version " + std::to_string(kVersionMajor) +
                     ".x and older (byte offset 8)"};
    const auto headerSize = r.get<std::uint32_t>();
    h.createdUnixNs = r.get<std::int64_t>();
    (void)r.get<std::uint32_t>();
    const auto storedCrc = r.get<std::uint32_t>();
    if (headerSize != kFileHeaderSize ||
        !checksumMatches(storedCrc, checksumOf(bytes.first(kFileHeaderSize - 4))))
        return Error{file + ": damaged file header (checksum mismatch at byte offset 28)"};
    return h;
}

void appendChunkHeader(std::vector<std::uint8_t>& out, const ChunkHeader& header) {
    const std::size_t start = out.size();
    ByteWriter w(out);
    w.put(kChunkSync);
    w.put(static_cast<std::uint32_t>(header.type));
    w.put(header.payloadSize);
    w.put(header.frameIndex);
    w.put(header.timestampNs);
    w.put(header.payloadChecksum);
    w.put(checksumOf({out.data() + start, out.size() - start}));
}

std::optional<ChunkHeader> decodeChunkHeader(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < kChunkHeaderSize)
        return std::nullopt;
    ByteReader r(bytes.first(kChunkHeaderSize), 0);
    if (r.get<std::uint32_t>() != kChunkSync)
        return std::nullopt;
    ChunkHeader h;
    h.type = static_cast<ChunkType>(r.get<std::uint32_t>());
    h.payloadSize = r.get<std::uint64_t>();
    h.frameIndex = r.get<std::uint64_t>();
    h.timestampNs = r.get<std::int64_t>();
    h.payloadChecksum = r.get<std::uint32_t>();
    if (!checksumMatches(r.get<std::uint32_t>(), checksumOf(bytes.first(kChunkHeaderSize - 4))))
        return std::nullopt;
    return h;
}

std::vector<std::uint8_t> encodeTrailer(const Trailer& trailer) {
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.put(trailer.indexOffset);
    w.put(trailer.frameCount);
    w.put(kTrailerMagic);
    w.put(checksumOf(out));
    return out;
}

std::optional<Trailer> decodeTrailer(std::span<const std::uint8_t> bytes) {
    if (bytes.size() != kTrailerSize)
        return std::nullopt;
    ByteReader r(bytes, 0);
    Trailer t;
    t.indexOffset = r.get<std::uint64_t>();
    t.frameCount = r.get<std::uint64_t>();
    if (r.get<std::uint32_t>() != kTrailerMagic ||
        !checksumMatches(r.get<std::uint32_t>(), checksumOf(bytes.first(kTrailerSize - 4))))
        return std::nullopt;
    return t;
}

std::vector<std::uint8_t> encodeIndex(std::span<const IndexEntry> entries) {
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.put(static_cast<std::uint64_t>(entries.size()));
    for (const IndexEntry& e : entries) {
        w.put(e.offset);
        w.put(e.timestampNs);
    }
    return out;
}

std::optional<std::vector<IndexEntry>> decodeIndex(std::span<const std::uint8_t> payload) {
    ByteReader r(payload, 0);
    const auto count = r.get<std::uint64_t>();
    if (!r.ok() || count > r.remaining() / 16 || r.remaining() != count * 16)
        return std::nullopt;
    std::vector<IndexEntry> entries(count);
    for (IndexEntry& e : entries) {
        e.offset = r.get<std::uint64_t>();
        e.timestampNs = r.get<std::int64_t>();
    }
    return entries;
}

std::string chunkTypeName(std::uint32_t type) {
    std::string name;
    for (int i = 0; i < 4; ++i) {
        const char c = static_cast<char>((type >> (8 * i)) & 0xff);
        name += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return name;
}

} // namespace dc::devices::recording
