// depthcloud record: any source to a depthcloud recording, through the same Session as the viewer; to an
// MCAP file of ROS 2 messages when OUT ends in .mcap.

#include "base/log.h"
#include "devices/recording/session_recording.h"
#include "devices/replay/replay_spec.h"
#include "devices/source_spec.h"
#include "exporting/export.h"
#include "tool/options.h"
#include "tool/recording_commands.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>

namespace dc::tool {

namespace {

volatile std::sig_atomic_t gStopRequested = 0;

void requestStop(int) {
    gStopRequested = 1;
}

devices::recording::RecordingOptions recordingOptions(const RecordOptions& o) {
    devices::recording::RecordingOptions r;
    r.color = o.color == "jpeg" ? devices::recording::ColorStorage::Jpeg
                                : devices::recording::ColorStorage::AsCaptured;
    r.jpegQuality = o.jpegQuality;
    r.compress = o.compression == "zstd";
    r.zstdLevel = o.zstdLevel;
    r.overwrite = o.overwrite;
    r.queueFrames = static_cast<std::size_t>(o.queueFrames);
    return r;
}

void printProgress(const devices::recording::RecorderStats& s, double seconds) {
    std::fprintf(stderr, "\rrecording: %.1f s, %llu frames written, %llu dropped, %.1f MB   ", seconds,
                 static_cast<unsigned long long>(s.framesWritten),
                 static_cast<unsigned long long>(s.framesDropped), static_cast<double>(s.bytesWritten) / 1e6);
}

// Waits for the frame limit, the time limit, a signal or the source's end; the reason if it failed.
std::string waitForEnd(devices::Session& session, const devices::recording::SessionRecording& recording,
                       const RecordOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    auto lastPrint = start;
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - start).count();
        for (const devices::SessionEvent& e : session.drainEvents()) {
            if (e.kind == devices::SessionEvent::Kind::EndOfStream)
                return {};
            if (e.kind == devices::SessionEvent::Kind::Error ||
                (e.kind == devices::SessionEvent::Kind::StateChanged &&
                 e.state == devices::DeviceState::Disconnected))
                return "the source failed: " + e.message;
        }
        if (!recording.stats().error.empty())
            return recording.stats().error;
        if (gStopRequested || recording.reachedLimit() || (o.seconds && seconds >= *o.seconds))
            return {};
        if (now - lastPrint >= std::chrono::seconds(1)) {
            printProgress(recording.stats(), seconds);
            lastPrint = now;
        }
    }
}

bool isMcap(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return extension == ".mcap";
}

// An MCAP is recorded as a .dcrec beside it first: the recorder never blocks capture and drops rather than
// falls behind, which a writer serialising ROS messages on the capture's heels could not promise. The
// .dcrec (OUT.dcrec) is converted once the recording stops and removed once the MCAP is whole.
std::string recordingPathFor(const RecordOptions& o) {
    return isMcap(o.out) ? o.out + ".dcrec" : o.out;
}

Status checkMcapDestination(const RecordOptions& o) {
    std::error_code ec;
    if (std::filesystem::is_directory(o.out, ec))
        return Error{o.out + " is a directory"};
    if (!o.overwrite && std::filesystem::exists(o.out, ec))
        return Error{o.out + " already exists (pass --overwrite to replace it)"};
    // The intermediate recording is never replaced: one left there is a take that did not convert.
    return devices::recording::RecordingWriter::checkDestination(recordingPathFor(o), false);
}

// The finished recording as OUT.mcap; the recording is removed once the MCAP is written, kept otherwise.
int convertToMcap(const std::string& recording, const RecordOptions& o) {
    auto source = devices::replay::openReplaySpecSource("replay:" + recording);
    exporting::ExportOptions options;
    options.format = exporting::ExportFormat::Mcap;
    options.outDirectory = o.out;
    options.overwrite = o.overwrite;
    auto result = source ? exporting::exportFrames(**source, options)
                         : Expected<exporting::ExportResult>(source.error());
    if (!result)
        return commandFailed("record", "converting to MCAP: " + result.error().message +
                                           " (the frames are kept in " + recording + ")");
    std::error_code ec;
    std::filesystem::remove(recording, ec);
    std::printf("depthcloud record: converted %zu frames to %s\n", result->framesWritten, o.out.c_str());
    return kExitOk;
}

} // namespace

int runRecord(const RecordOptions& o) {
    setLogQuiet(true);
    const std::string path = recordingPathFor(o);
    if (Status s = isMcap(o.out) ? checkMcapDestination(o)
                                 : devices::recording::RecordingWriter::checkDestination(o.out, o.overwrite);
        !s)
        return commandFailed("record", "OUT: " + s.error().message, kExitBadArguments);
    auto device = devices::openSourceSpec(o.source);
    if (!device)
        return commandFailed("record", "--source: " + device.error().message, kExitBadArguments);
    devices::Session session(std::move(*device));
    std::optional<std::uint64_t> limit;
    if (o.frames)
        limit = static_cast<std::uint64_t>(*o.frames);
    auto recording = devices::recording::SessionRecording::start(session, path, recordingOptions(o), limit);
    if (!recording)
        return commandFailed("record", recording.error().message);
    std::signal(SIGINT, requestStop);
    std::signal(SIGTERM, requestStop);
    if (Status s = session.start(); !s) {
        (void)(*recording)->stop();
        return commandFailed("record", s.error().message);
    }
    const auto start = std::chrono::steady_clock::now();
    const std::string problem = waitForEnd(session, **recording, o);
    session.stop();
    const Status closed = (*recording)->stop();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto stats = (*recording)->stats();
    printProgress(stats, seconds);
    std::fprintf(stderr, "\n");
    if (!closed)
        return commandFailed("record", closed.error().message);
    std::printf("depthcloud record: wrote %llu frames (%llu dropped, %.1f MB) to %s\n",
                static_cast<unsigned long long>(stats.framesWritten),
                static_cast<unsigned long long>(stats.framesDropped),
                static_cast<double>(stats.bytesWritten) / 1e6, path.c_str());
    const int converted = isMcap(o.out) ? convertToMcap(path, o) : kExitOk;
    if (!problem.empty())
        return commandFailed("record", problem + " (the frames before it are recorded)");
    return converted;
}

} // namespace dc::tool
