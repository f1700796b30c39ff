#pragma once

#include "base/mapped_file.h"
#include "devices/recording/format.h"
#include "devices/recording/frame_codec.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dc::devices::recording {

// Random access to a recording. A closed file opens through its index (O(1) per frame); a file whose
// index is missing (killed recorder), damaged or in disagreement with its chunks is recovered by
// scanning the chunks, and warnings() says what was found. Not thread-safe: one thread decodes.
class RecordingReader {
public:
    static Expected<RecordingReader> open(const std::string& path);
    // Reads a recording held in memory; `bytes` must outlive the reader (fuzz targets, tests).
    static Expected<RecordingReader> fromBytes(std::span<const std::uint8_t> bytes, const std::string& name);

    RecordingReader(RecordingReader&&) noexcept = default;
    RecordingReader& operator=(RecordingReader&&) noexcept = default;

    const std::string& name() const { return name_; }
    const FileHeader& header() const { return header_; }
    // Empty when the description chunk is missing or damaged.
    const std::optional<DeviceInfo>& device() const { return device_; }
    std::size_t frameCount() const { return entries_.size(); }
    std::int64_t timestampNs(std::size_t i) const { return entries_[i].timestampNs; }
    bool openedThroughIndex() const { return openedThroughIndex_; }
    const std::vector<std::string>& warnings() const { return warnings_; }

    // Decodes frame i (< frameCount()). A damaged chunk is an error naming file, frame and byte offset.
    Expected<frame::Frame> frame(std::size_t i);

private:
    RecordingReader() = default;
    Status load();
    bool loadIndex();
    void scanChunks();
    std::string indexProblem(const std::vector<IndexEntry>& entries) const;
    void readDescription(std::uint64_t offset, const ChunkHeader& header);
    std::span<const std::uint8_t> at(std::uint64_t offset, std::uint64_t size) const {
        return bytes_.subspan(static_cast<std::size_t>(offset), static_cast<std::size_t>(size));
    }
    std::string where(std::uint64_t offset) const {
        return name_ + " (byte offset " + std::to_string(offset) + ")";
    }

    std::string name_;
    base::MappedRegion file_;
    std::span<const std::uint8_t> bytes_;
    FileHeader header_;
    std::optional<DeviceInfo> device_;
    std::vector<IndexEntry> entries_;
    std::vector<std::string> warnings_;
    bool openedThroughIndex_ = false;
    FrameDecoder decoder_;
};

} // namespace dc::devices::recording
