#pragma once

#include "base/mutex.h"
#include "base/worker.h"
#include "devices/recording/recording_writer.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dc::devices::recording {

struct RecorderOptions {
    WriterOptions writer;
    // Frames accepted but not yet written. Frames are shared, not copied, so this bounds memory to this
    // many frames; one second of a 30 fps camera absorbs a slow disk's hiccups.
    std::size_t queueFrames = 30;
    // Threads that encode (compress) frames in parallel; one more thread writes them in order. Two keep
    // 1280x720 depth + color at 30 fps on a 2-core machine.
    int encoderThreads = 2;
    // The fault-injection seam: called with each frame's number (0, 1, ...) just before it is encoded,
    // on an encoder thread; a test throws from it to play an encoder that fails.
    std::function<void(std::uint64_t)> encodeFault;
};

struct RecorderStats {
    std::uint64_t framesWritten = 0;
    std::uint64_t framesDropped = 0; // arrived while the queue was full (or after the writer failed)
    std::uint64_t bytesWritten = 0;
    std::size_t queueDepth = 0; // accepted, not yet written
    double encodeSeconds = 0.0; // summed over the encoder threads
    double writeSeconds = 0.0;  // the writer thread's time in write calls
    std::string error;          // the first failure, once there is one
};

// Records frames without ever stalling the caller: push() queues the frame or, when the queue is full,
// drops it and counts the drop. Encoder threads compress frames in parallel and one writer thread
// appends them to the file in the order they were pushed.
class Recorder {
public:
    static Expected<std::unique_ptr<Recorder>> start(const std::string& path, const DeviceInfo& device,
                                                     RecorderOptions options = {});
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Thread-safe; false when the frame was dropped.
    bool push(frame::FramePtr frame);
    RecorderStats stats() const;
    // Writes what is queued, closes the file and renames it to its destination. Idempotent; call it from
    // the thread that owns the Recorder.
    Status stop();

    const std::string& path() const { return path_; }

private:
    struct Encoded {
        std::int64_t timestampNs = 0;
        Expected<std::vector<std::uint8_t>> payload = std::vector<std::uint8_t>{};
    };

    Recorder(RecordingWriter writer, const RecorderOptions& options);
    void encodeLoop(EncodeOptions options);
    void writeLoop();
    void fail(const std::string& message) DC_REQUIRES(mutex_);

    std::string path_;
    RecordingWriter writer_; // writer thread only, until stop() has joined it
    std::size_t capacity_;
    std::function<void(std::uint64_t)> encodeFault_;
    mutable base::Mutex mutex_;
    std::condition_variable work_;    // encoders: a frame to encode, or stop
    std::condition_variable written_; // writer: an encoded frame, or the encoders ended
    std::deque<std::pair<std::uint64_t, frame::FramePtr>> pending_ DC_GUARDED_BY(mutex_);
    std::map<std::uint64_t, Encoded> encoded_ DC_GUARDED_BY(mutex_);
    std::uint64_t nextSequence_ DC_GUARDED_BY(mutex_) = 0;
    std::uint64_t nextToWrite_ DC_GUARDED_BY(mutex_) = 0;
    std::size_t inFlight_ DC_GUARDED_BY(mutex_) = 0;
    int encodersRunning_ DC_GUARDED_BY(mutex_) = 0;
    bool stopping_ DC_GUARDED_BY(mutex_) = false;
    bool failed_ DC_GUARDED_BY(mutex_) = false;
    RecorderStats stats_ DC_GUARDED_BY(mutex_);
    std::optional<Status> result_; // stop()'s caller only
    std::vector<base::Worker> encoders_;
    base::Worker writerThread_;
};

} // namespace dc::devices::recording
