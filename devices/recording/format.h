#pragma once

#include "base/expected.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

// The on-disk layout of a depthcloud recording (.dcrec). docs/recording-format.md is the reference;
// this header is its single implementation, shared by the writer, the reader and the fuzz targets.
namespace dc::devices::recording {

// PNG's trick: a text-mode transfer or a truncated download mangles the CR LF or the ^Z and is caught
// by the magic check instead of surfacing as a checksum error somewhere in the middle.
inline constexpr std::array<std::uint8_t, 8> kFileMagic{'D', 'C', 'R', 'E', 'C', 0x0D, 0x0A, 0x1A};
inline constexpr std::uint16_t kVersionMajor = 1; // a reader refuses files with a larger major
inline constexpr std::uint16_t kVersionMinor = 5; // additions a version-1 reader may skip
inline constexpr std::size_t kFileHeaderSize = 32;
inline constexpr std::size_t kChunkHeaderSize = 40;
inline constexpr std::size_t kTrailerSize = 24;

constexpr std::uint32_t fourCc(const char (&s)[5]) {
    return static_cast<std::uint32_t>(s[0]) | static_cast<std::uint32_t>(s[1]) << 8 |
           static_cast<std::uint32_t>(s[2]) << 16 | static_cast<std::uint32_t>(s[3]) << 24;
}

inline constexpr std::uint32_t kChunkSync = fourCc("DCCK");
inline constexpr std::uint32_t kTrailerMagic = fourCc("DCEN");

enum class ChunkType : std::uint32_t {
    Description = fourCc("DESC"),
    Frame = fourCc("FRAM"),
    Index = fourCc("INDX"),
};

// Largest side and pixel count a reader accepts, so a damaged size field cannot ask for gigabytes.
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::uint64_t kMaxImagePixels = 64ull << 20;

// The low 32 bits of XXH3-64 (libxxhash): ample to detect damage, and fast enough (tens of GB/s) that
// checking every payload on every decode costs next to nothing.
std::uint32_t checksumOf(std::span<const std::uint8_t> bytes);
// Fuzzing builds (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, as libpng and zlib do) accept every checksum
// so that mutated inputs reach the parsers behind them instead of all stopping at the first check.
bool checksumMatches(std::uint32_t stored, std::uint32_t computed);

struct FileHeader {
    std::uint16_t versionMajor = kVersionMajor;
    std::uint16_t versionMinor = kVersionMinor;
    std::int64_t createdUnixNs = 0;
};

struct ChunkHeader {
    ChunkType type = ChunkType::Frame;
    std::uint64_t payloadSize = 0;
    std::uint64_t frameIndex = 0;      // Frame chunks: position in the recording
    std::int64_t timestampNs = 0;      // Frame chunks: the frame's timestamp (the index needs no payload)
    std::uint32_t payloadChecksum = 0; // of the payload bytes as stored
};

// Points at the index chunk; the last kTrailerSize bytes of a cleanly closed file.
struct Trailer {
    std::uint64_t indexOffset = 0;
    std::uint64_t frameCount = 0;
};

struct IndexEntry {
    std::uint64_t offset = 0; // of the frame's chunk header
    std::int64_t timestampNs = 0;
};

std::vector<std::uint8_t> encodeFileHeader(const FileHeader& header);
// `file` names the file in errors. A newer major version is an error of its own.
Expected<FileHeader> decodeFileHeader(std::span<const std::uint8_t> bytes, const std::string& file);

void appendChunkHeader(std::vector<std::uint8_t>& out, const ChunkHeader& header);
// Empty when the 40 bytes are not a chunk header (wrong sync word or header checksum).
std::optional<ChunkHeader> decodeChunkHeader(std::span<const std::uint8_t> bytes);

std::vector<std::uint8_t> encodeTrailer(const Trailer& trailer);
std::optional<Trailer> decodeTrailer(std::span<const std::uint8_t> bytes);

std::vector<std::uint8_t> encodeIndex(std::span<const IndexEntry> entries);
std::optional<std::vector<IndexEntry>> decodeIndex(std::span<const std::uint8_t> payload);

std::string chunkTypeName(std::uint32_t type);

} // namespace dc::devices::recording
