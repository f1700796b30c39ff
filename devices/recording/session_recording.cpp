#include "devices/recording/session_recording.h"

#include "base/log.h"

namespace dc::devices::recording {

RecorderOptions recorderOptionsFor(const RecordingOptions& o) {
    RecorderOptions r;
    r.writer.encode = {o.compress, o.zstdLevel, o.color, o.jpegQuality};
    r.writer.overwrite = o.overwrite;
    r.queueFrames = o.queueFrames;
    return r;
}

Expected<std::unique_ptr<SessionRecording>> SessionRecording::start(Session& session, const std::string& path,
                                                                    const RecordingOptions& options,
                                                                    std::optional<std::uint64_t> maxFrames) {
    return start(session, path, recorderOptionsFor(options), maxFrames);
}

Expected<std::unique_ptr<SessionRecording>> SessionRecording::start(Session& session, const std::string& path,
                                                                    RecorderOptions options,
                                                                    std::optional<std::uint64_t> maxFrames) {
    auto recorder = Recorder::start(path, {session.description(), session.capabilities()}, options);
    if (!recorder)
        return recorder.error();
    std::unique_ptr<SessionRecording> recording(
        new SessionRecording(session, std::move(*recorder), maxFrames));
    session.setFrameTap([r = recording.get()](const frame::FramePtr& frame) { r->offer(frame); });
    return recording;
}

SessionRecording::~SessionRecording() {
    if (Status s = stop(); !s)
        logError(s.error().message);
}

void SessionRecording::offer(const frame::FramePtr& frame) {
    if (maxFrames_ && offered_.load() >= *maxFrames_)
        return;
    ++offered_;
    recorder_->push(frame);
}

Status SessionRecording::stop() {
    if (!detached_) {
        session_.setFrameTap({}); // returns once no tap call is running
        detached_ = true;
    }
    return recorder_->stop();
}

} // namespace dc::devices::recording
