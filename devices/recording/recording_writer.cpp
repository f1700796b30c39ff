#include "devices/recording/recording_writer.h"

#include "base/files.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <unistd.h>

namespace dc::devices::recording {

namespace {

std::int64_t unixNowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

} // namespace

Status RecordingWriter::checkDestination(const std::string& path, bool overwrite) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!overwrite && fs::exists(path, ec))
        return Error{path + " already exists (pass --overwrite to replace it)"};
    const std::string partial = partialPathFor(path);
    if (fs::exists(partial, ec))
        return Error{partial + " exists: it holds an interrupted recording (replay it with --source replay:" +
                     partial + ", then move or remove it)"};
    const fs::path directory = fs::path(path).parent_path();
    if (!directory.empty() && !fs::is_directory(directory, ec))
        return Error{path + ": no such directory " + directory.string()};
    return {};
}

Expected<RecordingWriter> RecordingWriter::create(const std::string& path, const DeviceInfo& device,
                                                  WriterOptions options) {
    if (Status s = checkDestination(path, options.overwrite); !s)
        return s.error();
    const std::string partial = partialPathFor(path);
    base::UniqueFd file(::open(partial.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644));
    if (!file.valid()) {
        if (errno == EEXIST)
            return Error{partial +
                         " exists: it holds an interrupted recording (replay it with --source replay:" +
                         partial + ", then move or remove it)"};
        return Error{"cannot create " + partial + ": " + std::strerror(errno)};
    }
    RecordingWriter writer;
    writer.path_ = path;
    writer.options_ = options;
    writer.file_ = std::move(file);
    writer.encoder_ = FrameEncoder(options.encode);
    writer.lastSync_ = std::chrono::steady_clock::now();
    const auto header = encodeFileHeader({kVersionMajor, kVersionMinor, unixNowNs()});
    if (const int r = base::writeAll(writer.file_.get(), header); r < 0)
        return Error{"cannot write " + partial + ": " + std::strerror(-r)};
    writer.offset_ = header.size();
    if (Status s = writer.writeChunk({ChunkType::Description, 0, 0, 0, 0}, encodeDescription(device)); !s)
        return s.error();
    return writer;
}

Status RecordingWriter::writeChunk(ChunkHeader header, std::span<const std::uint8_t> payload) {
    header.payloadSize = payload.size();
    header.payloadChecksum = checksumOf(payload);
    std::vector<std::uint8_t> head;
    appendChunkHeader(head, header);
    if (const int r = base::writeAll(file_.get(), head, payload); r < 0)
        return Error{"cannot write " + partialPath() + " at byte offset " + std::to_string(offset_) + ": " +
                     std::strerror(-r)};
    offset_ += head.size() + payload.size();
    return {};
}

Status RecordingWriter::syncIfDue(bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (force) {
        if (::fdatasync(file_.get()) != 0)
            return Error{"cannot sync " + partialPath() + ": " + std::strerror(errno)};
        return {};
    }
    if (options_.syncInterval.count() <= 0 || now - lastSync_ < options_.syncInterval)
        return {};
    lastSync_ = now;
    // Starts writing back what the last interval added and returns at once: fdatasync here would stall
    // the writer for as long as the disk takes, and frames would queue up and drop behind it.
    if (::sync_file_range(file_.get(), static_cast<off64_t>(syncedUpTo_), 0, SYNC_FILE_RANGE_WRITE) != 0)
        return Error{"cannot flush " + partialPath() + ": " + std::strerror(errno)};
    syncedUpTo_ = offset_;
    return {};
}

Status RecordingWriter::append(const frame::Frame& frame) {
    auto payload = encoder_.encode(frame);
    if (!payload)
        return Error{path_ + ": frame " + std::to_string(index_.size()) + ": " + payload.error().message};
    return appendEncoded(*payload, frame.timestampNs);
}

Status RecordingWriter::appendEncoded(std::span<const std::uint8_t> payload, std::int64_t timestampNs) {
    if (finished_ || !file_.valid())
        return Error{"recording " + path_ + " is already closed"};
    const IndexEntry entry{offset_, timestampNs};
    if (Status s = writeChunk({ChunkType::Frame, 0, index_.size(), timestampNs, 0}, payload); !s)
        return s;
    index_.push_back(entry);
    return syncIfDue(false);
}

Status RecordingWriter::finish() {
    if (finished_ || !file_.valid())
        return Error{"recording " + path_ + " is already closed"};
    finished_ = true;
    const std::uint64_t indexOffset = offset_;
    if (Status s = writeChunk({ChunkType::Index, 0, 0, 0, 0}, encodeIndex(index_)); !s)
        return s;
    const auto trailer = encodeTrailer({indexOffset, index_.size()});
    if (const int r = base::writeAll(file_.get(), trailer); r < 0)
        return Error{"cannot write " + partialPath() + ": " + std::strerror(-r)};
    offset_ += trailer.size();
    if (Status s = syncIfDue(true); !s)
        return s;
    file_.reset();
    return base::renameInto(partialPath(), path_, options_.overwrite,
                            path_ + " appeared while recording; the recording is kept at " + partialPath());
}

} // namespace dc::devices::recording
