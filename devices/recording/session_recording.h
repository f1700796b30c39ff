#pragma once

#include "devices/recording/recorder.h"
#include "devices/session.h"

#include <atomic>
#include <memory>
#include <optional>

namespace dc::devices::recording {

// What a user chooses when starting a recording: the GUI's controls and `depthcloud record`'s flags fill
// the same struct. Depth and confidence are always stored losslessly.
struct RecordingOptions {
    ColorStorage color = ColorStorage::Jpeg; // the camera image: JPEG (the GUI's default) or as captured
    int jpegQuality = 90;                    // 1 (smallest) .. 100 (best)
    bool compress = true;                    // zstd on depth, confidence and an as-captured image
    int zstdLevel = 1;                       // 1 .. 19
    bool overwrite = false;                  // replace an existing file at the destination
    std::size_t queueFrames = 30;            // frames the writer may fall behind before dropping
};

// The recorder's settings for `options`, with as many encoder threads as keep up on this machine.
RecorderOptions recorderOptionsFor(const RecordingOptions& options);

// Records what a running Session captures, from the capture thread through the session's frame tap into
// a Recorder (never blocking capture). What the record button and `depthcloud record` both use.
// start(), stats() and stop() may be called from any one thread (the UI's); the session must outlive it.
class SessionRecording {
public:
    // Records every frame captured from now on, at most maxFrames when given.
    static Expected<std::unique_ptr<SessionRecording>> start(Session& session, const std::string& path,
                                                             const RecordingOptions& options = {},
                                                             std::optional<std::uint64_t> maxFrames = {});
    // The same with the recorder's own settings (benchmarks choose threads and write-back).
    static Expected<std::unique_ptr<SessionRecording>> start(Session& session, const std::string& path,
                                                             RecorderOptions options,
                                                             std::optional<std::uint64_t> maxFrames = {});
    ~SessionRecording();
    SessionRecording(const SessionRecording&) = delete;
    SessionRecording& operator=(const SessionRecording&) = delete;

    RecorderStats stats() const { return recorder_->stats(); }
    // Frames the session delivered to the recording (written + dropped + queued).
    std::uint64_t framesOffered() const { return offered_.load(); }
    bool reachedLimit() const { return maxFrames_ && offered_.load() >= *maxFrames_; }
    const std::string& path() const { return recorder_->path(); }
    // Detaches from the session, writes what is queued and closes the file. Idempotent.
    Status stop();

private:
    SessionRecording(Session& session, std::unique_ptr<Recorder> recorder,
                     std::optional<std::uint64_t> maxFrames)
        : session_(session), recorder_(std::move(recorder)), maxFrames_(maxFrames) {}
    void offer(const frame::FramePtr& frame);

    Session& session_;
    std::unique_ptr<Recorder> recorder_;
    std::optional<std::uint64_t> maxFrames_;
    std::atomic<std::uint64_t> offered_{0};
    bool detached_ = false;
};

} // namespace dc::devices::recording
