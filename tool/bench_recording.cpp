// depthcloud bench replay / bench record: decode throughput of replay sources, and recording throughput,
// drops and size at 1280x720 depth + color @30 fps.

#include "base/log.h"
#include "devices/frame_list_device.h"
#include "devices/recording/session_recording.h"
#include "devices/replay/importers.h"
#include "devices/session.h"
#include "devices/synthetic/synthetic_device.h"
#include "frame/rgb_image.h"
#include "tool/options.h"
#include "tool/recording_commands.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sched.h>
#include <thread>
#include <unistd.h>
#include <vector>

#ifdef DC_HAVE_ROS
#include "devices/ros/bag_reader.h"
#endif

namespace dc::tool {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Decodes every frame of `source` `passes` times; prints the median pass as frames per second and as a
// multiple of real time (a single pass of a short recording lasts a fraction of a second: too noisy alone).
// Returns the median seconds of one pass.
double decodeAll(const std::string& name, devices::replay::ReplaySource& source, bool color, int passes) {
    source.setDecodeColor(color);
    const std::size_t n = source.frameCount();
    const double recordedSeconds = static_cast<double>(source.timestampNs(n - 1) - source.timestampNs(0)) *
                                   1e-9 * static_cast<double>(n) /
                                   static_cast<double>(std::max<std::size_t>(n - 1, 1));
    std::size_t failed = 0;
    std::vector<double> seconds;
    for (int pass = 0; pass < passes; ++pass) {
        const auto start = Clock::now();
        for (std::size_t i = 0; i < n; ++i)
            failed += devices::replay::loadFrame(source, i) ? 0 : 1;
        seconds.push_back(secondsSince(start));
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    std::printf("  %-44s %5zu frames, median of %d passes %6.2f s: %7.1f fps = %6.1fx real time%s\n",
                name.c_str(), n, passes, median, static_cast<double>(n) / median, recordedSeconds / median,
                failed ? (" (" + std::to_string(failed) + " failed)").c_str() : "");
    return median;
}

// Frames of a synthetic camera, generated as fast as it can.
std::vector<frame::FramePtr> syntheticFrames(devices::SyntheticConfig config, int count) {
    config.paced = false;
    devices::SyntheticDevice device(config);
    std::vector<frame::FramePtr> frames;
    if (!device.open() || !device.start())
        return frames;
    while (static_cast<int>(frames.size()) < count) {
        auto r = device.capture(std::chrono::milliseconds(1000));
        if (r.kind == devices::CaptureResult::Kind::Frame)
            frames.push_back(r.frame);
    }
    return frames;
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

void runRecordCase(const RecordCase& c, const std::vector<frame::FramePtr>& frames,
                   const BenchRecordOptions& o) {
    const std::string path = tempPath(o.directory, c.name);
    auto device =
        std::make_unique<devices::FrameListDevice>(frames, 30.0, "synthetic 1280x720 + 1280x720 NV12");
    devices::Session session(std::move(device));
    devices::recording::RecorderOptions options;
    options.writer.encode = {c.compress, c.zstdLevel, c.color, 90};
    options.encoderThreads = c.threads;
    options.writer.syncInterval = std::chrono::milliseconds(o.syncMs);
    auto recording = devices::recording::SessionRecording::start(session, path, options);
    if (!recording || !session.start()) {
        std::printf("  %-8s cannot start: %s\n", c.name,
                    recording ? "session" : recording.error().message.c_str());
        return;
    }
    const auto start = Clock::now();
    while (secondsSince(start) < o.seconds)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    session.stop();
    const auto closing = Clock::now();
    const Status closed = (*recording)->stop();
    const double drainSeconds = secondsSince(closing);
    const auto s = (*recording)->stats();
    const double elapsed = secondsSince(start);
    std::printf("  %-8s %5llu offered %5llu written %4llu dropped  %6.1f MB/s written  %5.2f MB/frame  "
                "encode %4.0f%% "
                "write %3.0f%% of a core  close %.2f s%s\n",
                c.name, static_cast<unsigned long long>((*recording)->framesOffered()),
                static_cast<unsigned long long>(s.framesWritten),
                static_cast<unsigned long long>(s.framesDropped),
                static_cast<double>(s.bytesWritten) / 1e6 / elapsed,
                static_cast<double>(s.bytesWritten) / 1e6 /
                    static_cast<double>(std::max<std::uint64_t>(s.framesWritten, 1)),
                100.0 * s.encodeSeconds / elapsed, 100.0 * s.writeSeconds / elapsed, drainSeconds,
                closed ? "" : (" FAILED: " + closed.error().message).c_str());
    std::error_code ec;
    fs::remove(path, ec);
    fs::remove(path + ".partial", ec);
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

} // namespace

#ifdef DC_HAVE_ROS
// The frames as a RealSense-style bag: 16UC1 millimetres and rgb8, uncompressed, with camera_info.
Status writeBag(const std::string& path, const std::vector<frame::FramePtr>& frames) {
    auto bag = devices::ros::BagWriter::create(path);
    if (!bag)
        return bag.error();
    const frame::Intrinsics k = frames.front()->depthIntrinsics();
    devices::ros::RosCameraInfo info{static_cast<std::uint32_t>(k.width),
                                     static_cast<std::uint32_t>(k.height),
                                     {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1},
                                     "plumb_bob",
                                     {0, 0, 0, 0, 0}};
    if (Status s = (*bag)->write("/camera/depth/camera_info", frames.front()->timestampNs, info); !s)
        return s;
    for (const frame::FramePtr& f : frames) {
        const auto& depth = f->sceneDepth->depthMeters;
        devices::ros::RosImage d{f->timestampNs,
                                 "camera",
                                 "16UC1",
                                 static_cast<std::uint32_t>(depth.width),
                                 static_cast<std::uint32_t>(depth.height),
                                 static_cast<std::uint32_t>(2 * depth.width),
                                 false,
                                 std::vector<std::uint8_t>(depth.pixels.size() * 2)};
        for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
            const auto mm =
                static_cast<std::uint16_t>(std::clamp(depth.pixels[i] * 1000.0f + 0.5f, 0.0f, 65535.0f));
            std::memcpy(&d.data[2 * i], &mm, 2);
        }
        const auto& image = f->capturedImage;
        devices::ros::RosImage c{f->timestampNs,
                                 "camera",
                                 "rgb8",
                                 static_cast<std::uint32_t>(image.width),
                                 static_cast<std::uint32_t>(image.height),
                                 static_cast<std::uint32_t>(3 * image.width),
                                 false,
                                 frame::toRgb24(image)};
        if (Status s = (*bag)->write("/camera/depth/image_rect_raw", d); !s)
            return s;
        if (Status s = (*bag)->write("/camera/color/image_raw", c); !s)
            return s;
    }
    return (*bag)->close();
}

// The same 1280x720 depth + colour frames from our recording and from a ROS bag, decoded alike.
void benchBagAgainstRecording(const BenchReplayOptions& o) {
    devices::SyntheticConfig config;
    config.depthWidth = config.cameraWidth = 1280;
    config.depthHeight = config.cameraHeight = 720;
    config.motion = true;
    auto frames = syntheticFrames(config, o.bagFrames);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        auto f = std::make_shared<frame::Frame>(*frames[i]);
        // From 1 s: a bag refuses messages at time 0 (ros::TIME_MIN is 1 ns).
        f->timestampNs = 1'000'000'000 + static_cast<std::int64_t>(i) * 1'000'000'000 / 30;
        frames[i] = f;
    }
    const std::string recordingPath = tempPath({}, "replay-720p"), bagPath = recordingPath + ".bag";
    auto writer = devices::recording::RecordingWriter::create(recordingPath, {"synthetic 1280x720", {}});
    for (std::size_t i = 0; writer && i < frames.size(); ++i)
        (void)writer->append(*frames[i]);
    const bool recorded = writer && writer->finish();
    const Status bagged = writeBag(bagPath, frames);
    auto recording = devices::replay::openRecordingSource(recordingPath);
    auto bag = devices::replay::openReplaySource(bagPath);
    if (recorded && bagged && recording && bag) {
        const double ours =
            decodeAll("synthetic 1280x720 recording (zstd, NV12)", **recording, true, o.passes);
        const double ros = decodeAll("same frames as a ROS bag (16UC1 + rgb8)", **bag, true, o.passes);
        std::printf("  %-44s %.2fx the recording's time per frame\n", "ROS bag / recording", ros / ours);
    } else {
        std::printf("  1280x720 bag case: %s\n",
                    !bagged ? bagged.error().message.c_str() : "cannot write or open");
    }
    std::error_code ec;
    fs::remove(recordingPath, ec);
    fs::remove(bagPath, ec);
}
#endif

int runBenchReplay(const BenchReplayOptions& o) {
    setLogQuiet(true);
    std::printf("bench replay: decode throughput, headless, one thread (goal: >= 20x real time)\n");
    if (auto stray = devices::replay::openStraySource(o.stray); stray) {
        decodeAll("ARKit capture (Stray), depth+confidence+video", **stray, true, o.passes);
        decodeAll("ARKit capture (Stray), depth+confidence only", **stray, false, o.passes);
    } else {
        std::printf("  ARKit capture: %s\n", stray.error().message.c_str());
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
#ifdef DC_HAVE_ROS
    benchBagAgainstRecording(o);
#endif
    return kExitOk;
}

int runBenchRecord(const BenchRecordOptions& o) {
    setLogQuiet(true);
    pinToCores(o.cores);
    std::printf(
        "bench record: 1280x720 float depth + confidence + 1280x720 NV12 color @30 fps, %.0f s per case, "
        "%d cores (goal: 0 dropped)\n",
        o.seconds, o.cores);
    devices::SyntheticConfig config;
    config.depthWidth = config.cameraWidth = 1280;
    config.depthHeight = config.cameraHeight = 720;
    config.motion = true;
    const auto frames = syntheticFrames(config, 30);
    // Two encoder threads (the Recorder's default), and one case with a single one for comparison.
    const RecordCase cases[] = {
        {"raw", false, 1, devices::recording::ColorStorage::AsCaptured, 2},
        {"zstd1", true, 1, devices::recording::ColorStorage::AsCaptured, 2},
        {"zstd3", true, 3, devices::recording::ColorStorage::AsCaptured, 2},
        {"jpeg", true, 1, devices::recording::ColorStorage::Jpeg, 2},
        {"zstd1-1t", true, 1, devices::recording::ColorStorage::AsCaptured, 1},
    };
    for (const RecordCase& c : cases)
        if (o.only.empty() || o.only == c.name)
            runRecordCase(c, frames, o);
    return kExitOk;
}

} // namespace dc::tool
