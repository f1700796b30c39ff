#pragma once

#include "base/mutex.h"
#include "base/ordered_pool.h"
#include "devices/recording/frame_codec.h"
#include "devices/recording/recording_writer.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
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
// drops it and counts the drop. An ordered pool compresses frames in parallel and appends them to the file in
// the order they were pushed.
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
    // A pool worker's job: the frame numbered `number`, on the worker's own encoder.
    Encoded encode(const frame::FramePtr& frame, std::uint64_t number, std::size_t worker);
    // The pool's consumer: each frame's encoding, in the order the frames were pushed.
    void write(Expected<Encoded> encoded);
    void fail(const std::string& message) DC_REQUIRES(mutex_);

    std::string path_;
    RecordingWriter writer_; // the pool's delivering thread only, until stop() has finished the pool
    std::function<void(std::uint64_t)> encodeFault_;
    std::vector<FrameEncoder> encoders_; // one per pool worker, used by that worker only
    mutable base::Mutex mutex_;
    bool stopping_ DC_GUARDED_BY(mutex_) = false;
    bool failed_ DC_GUARDED_BY(mutex_) = false;
    RecorderStats stats_ DC_GUARDED_BY(mutex_); // but queueDepth, which is the pool's
    std::optional<Status> result_;              // stop()'s caller only
    // Encoders in parallel, the writer in push order. Last: its threads use everything above.
    base::OrderedPool<frame::FramePtr, Encoded> pool_;
};

} // namespace dc::devices::recording
