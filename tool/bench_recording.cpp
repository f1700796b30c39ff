// depthcloud bench replay / bench record: decode throughput of replay sources, and recording throughput,
// drops and size of a source's frames at its rate (by default 1280x720 depth + color @30 fps).

#include "base/files.h"
#include "base/log.h"
#include "devices/frame_list_device.h"
#include "devices/recording/session_recording.h"
#include "devices/replay/importers.h"
#include "devices/session.h"
#include "devices/source_spec.h"
#include "devices/synthetic/synthetic_device.h"
#include "tool/bench_frames.h"
#include "tool/bench_replay_formats.h"
#include "tool/options.h"
#include "tool/recording_commands.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace dc::tool {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// What a case records: a few distinct frames of one source, replayed at the source's own rate.
struct BenchFrames {
    std::vector<frame::FramePtr> frames;
    double fps = 30.0;
    std::string description;
};

constexpr int kRecordingDistinctFrames = 30;

std::string describe(const frame::Frame& f, double fps, const std::string& source) {
    char text[160];
    const int depthWidth = f.sceneDepth ? f.sceneDepth->depthMeters.width : 0;
    const int depthHeight = f.sceneDepth ? f.sceneDepth->depthMeters.height : 0;
    std::snprintf(text, sizeof text, "%s: %dx%d float depth + confidence + %dx%d color @%.0f fps",
                  source.c_str(), depthWidth, depthHeight, f.capturedImage.width, f.capturedImage.height,
                  fps);
    return text;
}

// The default: 1280x720 depth and color of the moving synthetic scene at 30 fps, made as fast as it can.
BenchFrames defaultFrames() {
    devices::SyntheticConfig config;
    config.depthWidth = config.cameraWidth = 1280;
    config.depthHeight = config.cameraHeight = 720;
    config.motion = true;
    BenchFrames b{syntheticFrames(config, kRecordingDistinctFrames), 30.0, {}};
    if (!b.frames.empty())
        b.description = describe(*b.frames.front(), b.fps, "synthetic");
    return b;
}

// The first frames `device` delivers, at the rate it announces.
Expected<BenchFrames> sourceFrames(devices::Device& device, const std::string& spec) {
    if (Status s = device.open(); !s)
        return s.error();
    if (Status s = device.start(); !s)
        return s.error();
    BenchFrames b;
    b.fps = device.capabilities().nominalFps > 0.0 ? device.capabilities().nominalFps : 30.0;
    for (int misses = 0; static_cast<int>(b.frames.size()) < kRecordingDistinctFrames && misses < 5;) {
        auto r = device.capture(std::chrono::milliseconds(1000));
        if (r.kind == devices::CaptureResult::Kind::Frame)
            b.frames.push_back(r.frame);
        else
            ++misses;
    }
    device.stop();
    if (b.frames.empty())
        return Error{"delivered no frames"};
    b.description = describe(*b.frames.front(), b.fps, spec);
    return b;
}

// The frames --source names (a bad spec is a bad argument), or the default ones. Returns the exit code.
int benchFrames(const BenchRecordOptions& o, BenchFrames& out) {
    if (o.source.empty()) {
        out = defaultFrames();
        return out.frames.empty() ? kExitFailure : kExitOk;
    }
    auto device = devices::openSourceSpec(o.source);
    if (!device) {
        std::fprintf(stderr, "depthcloud bench record: error: --source: %s\n",
                     device.error().message.c_str());
        return kExitBadArguments;
    }
    auto frames = sourceFrames(**device, o.source);
    if (!frames) {
        std::fprintf(stderr, "depthcloud bench record: error: %s: %s\n", o.source.c_str(),
                     frames.error().message.c_str());
        return kExitFailure;
    }
    out = std::move(*frames);
    return kExitOk;
}

std::string tempPath(const std::string& directory, const std::string& name) {
    const fs::path dir = directory.empty() ? fs::temp_directory_path() : fs::path(directory);
    return (dir / ("depthcloud-bench-" + std::to_string(::getpid()) + "-" + name + ".dcrec")).string();
}

struct RecordCase {
    const char* name;
    bool compress;
    int zstdLevel;
    devices::recording::ColorStorage color;
    int threads;
};

struct RecordCaseResult {
    std::string name;
    std::uint64_t offered = 0, written = 0, dropped = 0;
    double megabytesPerFrame = 0.0, megabytesPerSecond = 0.0;
    double encodeCorePercent = 0.0, writeCorePercent = 0.0; // of one core, over the run
    double closeSeconds = 0.0;                              // stop(): writing what was still queued
    std::string error;
};

RecordCaseResult runRecordCase(const RecordCase& c, const BenchFrames& frames, const BenchRecordOptions& o) {
    RecordCaseResult result;
    result.name = c.name;
    const std::string path = tempPath(o.directory, c.name);
    auto device = std::make_unique<devices::FrameListDevice>(frames.frames, frames.fps, frames.description);
    devices::Session session(std::move(device));
    devices::recording::RecorderOptions options;
    options.writer.encode = {c.compress, c.zstdLevel, c.color, 90};
    options.encoderThreads = c.threads;
    options.writer.syncInterval = std::chrono::milliseconds(o.syncMs);
    auto recording = devices::recording::SessionRecording::start(session, path, options);
    if (!recording || !session.start()) {
        result.error = recording ? "cannot start the session" : recording.error().message;
        return result;
    }
    const auto start = Clock::now();
    while (secondsSince(start) < o.seconds)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    session.stop();
    const auto closing = Clock::now();
    const Status closed = (*recording)->stop();
    result.closeSeconds = secondsSince(closing);
    const auto s = (*recording)->stats();
    const double elapsed = secondsSince(start);
    result.offered = (*recording)->framesOffered();
    result.written = s.framesWritten;
    result.dropped = s.framesDropped;
    result.megabytesPerSecond = static_cast<double>(s.bytesWritten) / 1e6 / elapsed;
    result.megabytesPerFrame = static_cast<double>(s.bytesWritten) / 1e6 /
                               static_cast<double>(std::max<std::uint64_t>(s.framesWritten, 1));
    result.encodeCorePercent = 100.0 * s.encodeSeconds / elapsed;
    result.writeCorePercent = 100.0 * s.writeSeconds / elapsed;
    if (!closed)
        result.error = closed.error().message;
    std::error_code ec;
    fs::remove(path, ec);
    fs::remove(path + ".partial", ec);
    return result;
}

// One line per case; the size relative to the raw case when it ran first (the same run's baseline).
void printCase(const RecordCaseResult& r, double rawMegabytesPerFrame) {
    char ratio[32] = "";
    if (rawMegabytesPerFrame > 0.0)
        std::snprintf(ratio, sizeof ratio, " (%.3fx raw)", r.megabytesPerFrame / rawMegabytesPerFrame);
    std::printf("  %-8s %5llu offered %5llu written %4llu dropped  %6.1f MB/s  %6.3f MB/frame%s  "
                "encode %4.0f%% write %3.0f%% of a core  close %.2f s%s\n",
                r.name.c_str(), static_cast<unsigned long long>(r.offered),
                static_cast<unsigned long long>(r.written), static_cast<unsigned long long>(r.dropped),
                r.megabytesPerSecond, r.megabytesPerFrame, ratio, r.encodeCorePercent, r.writeCorePercent,
                r.closeSeconds, r.error.empty() ? "" : (" FAILED: " + r.error).c_str());
}

void pinToCores(int cores) {
    if (cores <= 0)
        return;
    cpu_set_t set;
    CPU_ZERO(&set);
    const int available = static_cast<int>(std::thread::hardware_concurrency());
    for (int i = 0; i < std::min(cores, available); ++i)
        CPU_SET(i, &set);
    if (sched_setaffinity(0, sizeof(set), &set) != 0)
        std::printf("(could not pin to %d cores)\n", cores);
}

// Processes that each keep one core busy (on the cores this process is pinned to) while it exists: a
// recorder rarely has the machine to itself. They die with their parent, however it ends.
class CoreLoad {
public:
    explicit CoreLoad(int processes) {
        const pid_t parent = ::getpid();
        for (int i = 0; i < processes; ++i) {
            const pid_t child = ::fork();
            if (child == 0) {
                ::prctl(PR_SET_PDEATHSIG, SIGKILL);
                if (::getppid() != parent)
                    ::_exit(0);
                volatile double x = 1.0;
                for (;;)
                    x = x * 1.0000001 + 1e-9;
            }
            if (child > 0)
                children_.push_back(child);
        }
    }
    ~CoreLoad() {
        for (const pid_t child : children_) {
            ::kill(child, SIGKILL);
            ::waitpid(child, nullptr, 0);
        }
    }
    CoreLoad(const CoreLoad&) = delete;
    CoreLoad& operator=(const CoreLoad&) = delete;
    std::size_t running() const { return children_.size(); }

private:
    std::vector<pid_t> children_;
};

nlohmann::json toJson(const RecordCaseResult& r) {
    return {{"case", r.name},
            {"offered", r.offered},
            {"written", r.written},
            {"dropped", r.dropped},
            {"megabytesPerFrame", r.megabytesPerFrame},
            {"megabytesPerSecond", r.megabytesPerSecond},
            {"encodeCorePercent", r.encodeCorePercent},
            {"writeCorePercent", r.writeCorePercent},
            {"closeSeconds", r.closeSeconds},
            {"error", r.error}};
}

} // namespace

int runBenchReplay(const BenchReplayOptions& o) {
    setLogQuiet(true);
    std::printf("bench replay: decode throughput, headless, one thread (goal: >= 20x real time)\n");
    if (!o.data.empty()) {
        auto source = devices::replay::openReplaySource(o.data);
        if (!source) {
            std::fprintf(stderr, "depthcloud bench replay: error: --data: %s\n",
                         source.error().message.c_str());
            return kExitBadArguments;
        }
        const std::string name = (*source)->description();
        decodeAll(name + ", everything", **source, true, o.passes);
        decodeAll(name + ", without color", **source, false, o.passes);
    }
    devices::SyntheticConfig config;
    config.depthWidth = config.cameraWidth = 640;
    config.depthHeight = config.cameraHeight = 480;
    config.fps = 30.0;
    config.motion = true;
    const auto frames = syntheticFrames(config, o.syntheticFrames);
    const std::string path = tempPath({}, "replay");
    {
        auto writer = devices::recording::RecordingWriter::create(path, {"synthetic 640x480", {}});
        for (std::size_t i = 0; writer && i < frames.size(); ++i) {
            auto f = std::make_shared<frame::Frame>(*frames[i]);
            f->timestampNs = static_cast<std::int64_t>(i) * 1'000'000'000 / 30; // recorded at exactly 30 fps
            (void)writer->append(*f);
        }
        if (!writer || !writer->finish())
            std::printf("  cannot write %s\n", path.c_str());
    }
    if (auto recording = devices::replay::openRecordingSource(path); recording) {
        decodeAll("synthetic 640x480 recording (zstd, NV12)", **recording, true, o.passes);
        decodeAll("synthetic 640x480 recording, depth only", **recording, false, o.passes);
    }
    std::error_code ec;
    fs::remove(path, ec);
    benchReplayFormats(o.bagFrames, o.passes);
    return kExitOk;
}

int runBenchRecord(const BenchRecordOptions& o) {
    setLogQuiet(true);
    pinToCores(o.cores);
    BenchFrames frames;
    if (const int code = benchFrames(o, frames); code != kExitOk)
        return code;
    std::printf("bench record: %s, %.0f s per case, %d cores, %d of them loaded by another process (goal: 0 "
                "dropped)\n",
                frames.description.c_str(), o.seconds, o.cores, o.load);
    // The Recorder's default of two encoder threads, and cases with one for comparison.
    const RecordCase cases[] = {
        {"raw", false, 1, devices::recording::ColorStorage::AsCaptured, 2},
        {"zstd1", true, 1, devices::recording::ColorStorage::AsCaptured, 2},
        {"zstd3", true, 3, devices::recording::ColorStorage::AsCaptured, 2},
        {"jpeg", true, 1, devices::recording::ColorStorage::Jpeg, 2},
        {"zstd1-1t", true, 1, devices::recording::ColorStorage::AsCaptured, 1},
        {"jpeg-1t", true, 1, devices::recording::ColorStorage::Jpeg, 1},
    };
    const CoreLoad load(o.load); // after the frames are made: it only competes with the recording
    nlohmann::json results = nlohmann::json::array();
    double rawMegabytesPerFrame = 0.0;
    for (const RecordCase& c : cases) {
        if (!o.only.empty() && o.only != c.name)
            continue;
        const RecordCaseResult r = runRecordCase(c, frames, o);
        if (r.name == "raw")
            rawMegabytesPerFrame = r.megabytesPerFrame;
        printCase(r, rawMegabytesPerFrame);
        results.push_back(toJson(r));
    }
    if (o.jsonPath.empty())
        return kExitOk;
    const nlohmann::json report{{"frame", frames.description},     {"fps", frames.fps},
                                {"secondsPerCase", o.seconds},     {"cores", o.cores},
                                {"loadProcesses", load.running()}, {"cases", results}};
    if (Status s = base::writeTextFile(o.jsonPath, report.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud bench record: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
