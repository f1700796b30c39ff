#include "devices/recording/recording_reader.h"

#include <algorithm>

namespace dc::devices::recording {

Expected<RecordingReader> RecordingReader::open(const std::string& path) {
    auto file = base::mapFile(path);
    if (!file)
        return file.error();
    RecordingReader reader;
    reader.name_ = path;
    reader.file_ = std::move(*file);
    reader.bytes_ = reader.file_.bytes();
    if (Status s = reader.load(); !s)
        return s.error();
    return reader;
}

Expected<RecordingReader> RecordingReader::fromBytes(std::span<const std::uint8_t> bytes,
                                                     const std::string& name) {
    RecordingReader reader;
    reader.name_ = name;
    reader.bytes_ = bytes;
    if (Status s = reader.load(); !s)
        return s.error();
    return reader;
}

Status RecordingReader::load() {
    auto header = decodeFileHeader(bytes_, name_);
    if (!header)
        return header.error();
    header_ = *header;
    if (!loadIndex())
        scanChunks();
    if (!device_)
        warnings_.push_back(name_ + ": the device description chunk is missing or damaged");
    return {};
}

// True when the trailer, the index chunk and every frame chunk it points at agree.
bool RecordingReader::loadIndex() {
    if (bytes_.size() < kFileHeaderSize + kTrailerSize) {
        warnings_.push_back(name_ + ": no index (the file ends at byte offset " +
                            std::to_string(bytes_.size()) + "); recovering by scanning chunks");
        return false;
    }
    const std::uint64_t trailerAt = bytes_.size() - kTrailerSize;
    const auto trailer = decodeTrailer(at(trailerAt, kTrailerSize));
    if (!trailer) {
        warnings_.push_back(name_ + ": no index at the end of the file (the recording was not closed: killed "
                                    "or still being written); recovering by scanning chunks");
        return false;
    }
    const auto head =
        trailer->indexOffset <= trailerAt && trailerAt - trailer->indexOffset >= kChunkHeaderSize
            ? decodeChunkHeader(at(trailer->indexOffset, kChunkHeaderSize))
            : std::nullopt;
    const std::uint64_t payloadAt = trailer->indexOffset + kChunkHeaderSize;
    std::optional<std::vector<IndexEntry>> entries;
    if (head && head->type == ChunkType::Index && head->payloadSize <= trailerAt - payloadAt &&
        checksumMatches(head->payloadChecksum, checksumOf(at(payloadAt, head->payloadSize))))
        entries = decodeIndex(at(payloadAt, head->payloadSize));
    if (!entries || entries->size() != trailer->frameCount) {
        warnings_.push_back("damaged index in " + where(trailer->indexOffset) +
                            "; recovering by scanning chunks");
        return false;
    }
    if (const std::string problem = indexProblem(*entries); !problem.empty()) {
        warnings_.push_back("the index of " + name_ + " disagrees with its chunks: " + problem +
                            "; recovering by scanning chunks");
        return false;
    }
    entries_ = std::move(*entries);
    openedThroughIndex_ = true;
    if (const auto desc = decodeChunkHeader(
            at(kFileHeaderSize, std::min<std::uint64_t>(kChunkHeaderSize, bytes_.size() - kFileHeaderSize)));
        desc && desc->type == ChunkType::Description)
        readDescription(kFileHeaderSize, *desc);
    return true;
}

std::string RecordingReader::indexProblem(const std::vector<IndexEntry>& entries) const {
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const IndexEntry& e = entries[i];
        const std::string entry =
            "entry " + std::to_string(i) + " points at byte offset " + std::to_string(e.offset);
        if (e.offset < kFileHeaderSize || e.offset > bytes_.size() - kChunkHeaderSize)
            return entry + ", outside the file";
        const auto h = decodeChunkHeader(at(e.offset, kChunkHeaderSize));
        if (!h || h->type != ChunkType::Frame)
            return entry + ", where no frame chunk starts";
        if (h->frameIndex != i || h->timestampNs != e.timestampNs)
            return entry + ", where the chunk holds frame " + std::to_string(h->frameIndex) + " at " +
                   std::to_string(h->timestampNs) + " ns (index: " + std::to_string(e.timestampNs) + " ns)";
        if (h->payloadSize > bytes_.size() - e.offset - kChunkHeaderSize)
            return entry + ", whose chunk runs past the end of the file";
    }
    return {};
}

void RecordingReader::readDescription(std::uint64_t offset, const ChunkHeader& header) {
    if (header.payloadSize > bytes_.size() - offset - kChunkHeaderSize)
        return;
    const auto payload = at(offset + kChunkHeaderSize, header.payloadSize);
    if (checksumMatches(header.payloadChecksum, checksumOf(payload)))
        device_ = decodeDescription(payload);
}

void RecordingReader::scanChunks() {
    entries_.clear();
    std::uint64_t pos = kFileHeaderSize;
    std::uint64_t expectedFrame = 0;
    while (bytes_.size() - pos >= kChunkHeaderSize) {
        const auto h = decodeChunkHeader(at(pos, kChunkHeaderSize));
        if (!h) {
            if (bytes_.size() - pos == kTrailerSize && decodeTrailer(at(pos, kTrailerSize)))
                return;
            // Resynchronise on the next chunk header; its own checksum tells a real one from data.
            std::uint64_t next = pos + 1;
            while (bytes_.size() - next >= kChunkHeaderSize && !decodeChunkHeader(at(next, kChunkHeaderSize)))
                ++next;
            warnings_.push_back("damaged data in " + where(pos) + ": skipped " + std::to_string(next - pos) +
                                " bytes to the next chunk");
            pos = next;
            continue;
        }
        const std::uint64_t payloadAt = pos + kChunkHeaderSize;
        if (h->payloadSize > bytes_.size() - payloadAt) {
            warnings_.push_back(name_ + ": frame " + std::to_string(h->frameIndex) +
                                ": truncated chunk at byte offset " + std::to_string(pos) + " (needs " +
                                std::to_string(h->payloadSize) + " bytes, the file ends after " +
                                std::to_string(bytes_.size() - payloadAt) +
                                "); the frames before it are kept");
            return;
        }
        if (h->type == ChunkType::Frame) {
            if (h->frameIndex != expectedFrame)
                warnings_.push_back(name_ + ": frames " + std::to_string(expectedFrame) + " to " +
                                    std::to_string(h->frameIndex) + " are missing before byte offset " +
                                    std::to_string(pos));
            entries_.push_back({pos, h->timestampNs});
            expectedFrame = h->frameIndex + 1;
        } else if (h->type == ChunkType::Description && !device_) {
            readDescription(pos, *h);
        }
        pos = payloadAt + h->payloadSize;
    }
    if (pos != bytes_.size())
        warnings_.push_back(name_ + ": truncated file: " + std::to_string(bytes_.size() - pos) +
                            " stray bytes at byte offset " + std::to_string(pos));
}

Expected<frame::Frame> RecordingReader::frame(std::size_t i) {
    if (i >= entries_.size())
        return Error{name_ + ": frame " + std::to_string(i) + " does not exist (" +
                     std::to_string(entries_.size()) + " frames)"};
    const std::uint64_t offset = entries_[i].offset;
    const auto h = decodeChunkHeader(at(offset, kChunkHeaderSize));
    if (!h)
        return Error{name_ + ": frame " + std::to_string(i) + ": damaged chunk header at byte offset " +
                     std::to_string(offset)};
    const auto payload = at(offset + kChunkHeaderSize, h->payloadSize);
    const std::uint32_t checksum = checksumOf(payload);
    if (!checksumMatches(h->payloadChecksum, checksum))
        return Error{name_ + ": frame " + std::to_string(i) + ": chunk at byte offset " +
                     std::to_string(offset) + " fails its checksum (damaged data)"};
    auto frame = decoder_.decode(payload, offset + kChunkHeaderSize, name_, i);
    if (!frame)
        return frame.error();
    frame->timestampNs = h->timestampNs;
    return frame;
}

} // namespace dc::devices::recording
