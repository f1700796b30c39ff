#pragma once

#include "base/unique_fd.h"
#include "devices/recording/format.h"
#include "devices/recording/frame_codec.h"

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace dc::devices::recording {

struct WriterOptions {
    EncodeOptions encode;
    bool overwrite = false; // replace an existing file at the destination when the recording closes
    // Every chunk reaches the kernel as soon as it is encoded, so a killed recorder loses at most the
    // frame in flight; starting write-back at this interval also bounds what a power cut loses (about
    // this long, plus the disk's own delay). Zero: only at close.
    std::chrono::milliseconds syncInterval{1000};
};

// Writes one recording, synchronously, on the calling thread. The file grows under partialPath() and
// is renamed to its destination only by finish(), so a failed or killed recording never replaces a
// good file; what it wrote stays readable at partialPath().
class RecordingWriter {
public:
    static std::string partialPathFor(const std::string& path) { return path + ".partial"; }

    // Whether a recording may be written to `path`, checked before anything is recorded: an existing
    // destination is refused unless `overwrite`, an existing partial file always (it is an interrupted
    // recording that nothing may destroy), and so is a destination whose directory does not exist.
    static Status checkDestination(const std::string& path, bool overwrite);
    // Checks the destination (checkDestination) and creates the partial file.
    static Expected<RecordingWriter> create(const std::string& path, const DeviceInfo& device,
                                            WriterOptions options = {});

    RecordingWriter(RecordingWriter&&) noexcept = default;
    RecordingWriter& operator=(RecordingWriter&&) noexcept = default;
    ~RecordingWriter() = default;

    Status append(const frame::Frame& frame);
    // Appends a frame that a FrameEncoder made elsewhere (the Recorder encodes on several threads).
    Status appendEncoded(std::span<const std::uint8_t> payload, std::int64_t timestampNs);
    // Writes the index and trailer, syncs and renames to the destination. Nothing may follow.
    Status finish();

    std::uint64_t framesWritten() const { return index_.size(); }
    std::uint64_t bytesWritten() const { return offset_; }
    const std::string& path() const { return path_; }
    std::string partialPath() const { return partialPathFor(path_); }

private:
    RecordingWriter() = default;
    Status writeChunk(ChunkHeader header, std::span<const std::uint8_t> payload);
    Status syncIfDue(bool force);

    std::string path_;
    WriterOptions options_;
    base::UniqueFd file_;
    FrameEncoder encoder_;
    std::vector<IndexEntry> index_;
    std::uint64_t offset_ = 0;
    std::uint64_t syncedUpTo_ = 0; // write-back was started for the bytes before this offset
    std::chrono::steady_clock::time_point lastSync_;
    bool finished_ = false;
};

} // namespace dc::devices::recording
