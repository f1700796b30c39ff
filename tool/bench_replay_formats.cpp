// bench replay's format comparison: one set of frames written by each writer we have and read back by each
// reader, so a format's cost is its own and not its content's.

#include "tool/bench_replay_formats.h"

#include "devices/recording/recording_writer.h"
#include "devices/replay/importers.h"
#include "exporting/mcap_export.h"
#include "exporting/ros2_messages.h"
#include "frame/rgb_image.h"
#include "tool/bench_frames.h"

#ifdef DC_HAVE_ROS
#include "devices/ros/bag_reader.h"

#include <sqlite3.h>
#endif

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

namespace dc::tool {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Frames = std::vector<frame::FramePtr>;

constexpr const char* kDepthTopic = "/camera/camera/depth/image_rect_raw";
constexpr const char* kColourTopic = "/camera/camera/color/image_raw";
constexpr const char* kDepthInfoTopic = "/camera/camera/depth/camera_info";

// Synthetic 1280x720 frames, their depth in whole millimetres so that every format stores it as 16UC1.
Frames formatFrames(int count) {
    devices::SyntheticConfig config;
    config.depthWidth = config.cameraWidth = 1280;
    config.depthHeight = config.cameraHeight = 720;
    config.motion = true;
    Frames frames = syntheticFrames(config, count);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        auto f = std::make_shared<frame::Frame>(*frames[i]);
        // From 1 s: a bag refuses messages at time 0 (ros::TIME_MIN is 1 ns).
        f->timestampNs = 1'000'000'000 + static_cast<std::int64_t>(i) * 1'000'000'000 / 30;
        for (float& z : f->sceneDepth->depthMeters.pixels)
            z = std::round(z * 1000.0f) / 1000.0f;
        frames[i] = std::move(f);
    }
    return frames;
}

std::vector<std::uint8_t> millimetres(const frame::Plane<float>& depth) {
    std::vector<std::uint8_t> bytes(depth.pixels.size() * 2);
    for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
        const auto mm =
            static_cast<std::uint16_t>(std::clamp(depth.pixels[i] * 1000.0f + 0.5f, 0.0f, 65535.0f));
        std::memcpy(&bytes[2 * i], &mm, 2);
    }
    return bytes;
}

Status writeRecording(const std::string& path, const Frames& frames) {
    auto writer = devices::recording::RecordingWriter::create(path, {"synthetic 1280x720", {}});
    if (!writer)
        return writer.error();
    for (const frame::FramePtr& f : frames)
        if (Status s = writer->append(*f); !s)
            return s;
    return writer->finish();
}

#ifdef DC_HAVE_ROS
Status writeMcap(const std::string& path, const Frames& frames) {
    auto writer = exporting::McapFrameWriter::create(path, true);
    if (!writer)
        return writer.error();
    for (const frame::FramePtr& f : frames)
        if (Status s = (*writer)->add(*f); !s)
            return s;
    return (*writer)->finish();
}

using Database = std::unique_ptr<sqlite3, decltype(&sqlite3_close)>;

Status execute(sqlite3* db, const char* sql) {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) == SQLITE_OK)
        return Status::success();
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    return Error{text};
}

// A rosbag2 sqlite3 file as Humble's recorder lays it out: a topics table and one CDR blob per message.
Status writeDb3Messages(sqlite3* db, const Frames& frames) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &raw,
                           nullptr) != SQLITE_OK)
        return Error{sqlite3_errmsg(db)};
    const std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> insert(raw, &sqlite3_finalize);
    const auto add = [&](int topic, std::int64_t ns, const std::vector<std::uint8_t>& data) -> Status {
        sqlite3_bind_int(raw, 1, topic);
        sqlite3_bind_int64(raw, 2, ns);
        sqlite3_bind_blob(raw, 3, data.data(), static_cast<int>(data.size()), SQLITE_STATIC);
        const int stepped = sqlite3_step(raw);
        sqlite3_reset(raw);
        return stepped == SQLITE_DONE ? Status::success() : Status(Error{sqlite3_errmsg(db)});
    };
    const frame::Intrinsics k = frames.front()->depthIntrinsics();
    exporting::ros2::CameraInfo info{{exporting::ros2::stampOf(frames.front()->timestampNs), "camera"},
                                     static_cast<std::uint32_t>(k.height),
                                     static_cast<std::uint32_t>(k.width),
                                     "plumb_bob",
                                     {0, 0, 0, 0, 0},
                                     {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}};
    if (Status s = add(3, frames.front()->timestampNs, exporting::ros2::serialize(info)); !s)
        return s;
    for (const frame::FramePtr& f : frames) {
        const exporting::ros2::Header header{exporting::ros2::stampOf(f->timestampNs), "camera"};
        const auto& depth = f->sceneDepth->depthMeters;
        const auto& image = f->capturedImage;
        const exporting::ros2::Image d{
            header,  static_cast<std::uint32_t>(depth.height),    static_cast<std::uint32_t>(depth.width),
            "16UC1", static_cast<std::uint32_t>(2 * depth.width), millimetres(depth)};
        const exporting::ros2::Image c{
            header, static_cast<std::uint32_t>(image.height),    static_cast<std::uint32_t>(image.width),
            "rgb8", static_cast<std::uint32_t>(3 * image.width), frame::toRgb24(image)};
        if (Status s = add(1, f->timestampNs, exporting::ros2::serialize(d)); !s)
            return s;
        if (Status s = add(2, f->timestampNs, exporting::ros2::serialize(c)); !s)
            return s;
    }
    return Status::success();
}

Status writeDb3(const std::string& path, const Frames& frames) {
    sqlite3* raw = nullptr;
    const int opened =
        sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
    const Database db(raw, &sqlite3_close);
    if (opened != SQLITE_OK)
        return Error{path + ": " + sqlite3_errmsg(raw)};
    const std::string schema =
        std::string("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
                    "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
                    "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
                    "timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
                    "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
                    "INSERT INTO topics VALUES (1, '") +
        kDepthTopic + "', 'sensor_msgs/msg/Image', 'cdr', ''), (2, '" + kColourTopic +
        "', 'sensor_msgs/msg/Image', 'cdr', ''), (3, '" + kDepthInfoTopic +
        "', 'sensor_msgs/msg/CameraInfo', 'cdr', ''); BEGIN;";
    if (Status s = execute(db.get(), schema.c_str()); !s)
        return Error{path + ": " + s.error().message};
    if (Status s = writeDb3Messages(db.get(), frames); !s)
        return Error{path + ": " + s.error().message};
    return execute(db.get(), "COMMIT;");
}

devices::ros::RosImage rosImage(std::int64_t stampNs, const char* encoding, int width, int height,
                                int bytesPerPixel, std::vector<std::uint8_t> data) {
    return {stampNs,
            "camera",
            encoding,
            static_cast<std::uint32_t>(width),
            static_cast<std::uint32_t>(height),
            static_cast<std::uint32_t>(bytesPerPixel * width),
            false,
            std::move(data)};
}

// The frames as a RealSense-style ROS 1 bag: 16UC1 millimetres and rgb8, uncompressed, with camera_info.
Status writeBag(const std::string& path, const Frames& frames) {
    auto bag = devices::ros::BagWriter::create(path);
    if (!bag)
        return bag.error();
    const frame::Intrinsics k = frames.front()->depthIntrinsics();
    const devices::ros::RosCameraInfo info{static_cast<std::uint32_t>(k.width),
                                           static_cast<std::uint32_t>(k.height),
                                           {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1},
                                           "plumb_bob",
                                           {0, 0, 0, 0, 0}};
    if (Status s = (*bag)->write(kDepthInfoTopic, frames.front()->timestampNs, info); !s)
        return s;
    for (const frame::FramePtr& f : frames) {
        const auto& depth = f->sceneDepth->depthMeters;
        const auto& image = f->capturedImage;
        const auto d = rosImage(f->timestampNs, "16UC1", depth.width, depth.height, 2, millimetres(depth));
        const auto c = rosImage(f->timestampNs, "rgb8", image.width, image.height, 3, frame::toRgb24(image));
        if (Status s = (*bag)->write(kDepthTopic, d); !s)
            return s;
        if (Status s = (*bag)->write(kColourTopic, c); !s)
            return s;
    }
    return (*bag)->close();
}

#endif

struct Format {
    const char* name;
    const char* extension;
    Status (*write)(const std::string& path, const Frames& frames);
};

} // namespace

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
        seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    std::printf("  %-44s %5zu frames, median of %d passes %6.2f s: %7.1f fps = %6.1fx real time%s\n",
                name.c_str(), n, passes, median, static_cast<double>(n) / median, recordedSeconds / median,
                failed ? (" (" + std::to_string(failed) + " failed)").c_str() : "");
    return median;
}

void benchReplayFormats(int count, int passes) {
    const Frames frames = formatFrames(count);
    if (frames.empty())
        return;
    const Format formats[] = {
        {"synthetic 1280x720 recording (zstd, NV12)", ".dcrec", writeRecording},
#ifdef DC_HAVE_ROS
        {"same frames as a ROS 1 bag (16UC1 + rgb8)", ".bag", writeBag},
        {"same frames as MCAP (zstd, 16UC1 + rgb8)", ".mcap", writeMcap},
        {"same frames as a rosbag2 .db3 (16UC1 + rgb8)", ".db3", writeDb3},
#endif
    };
    double recordingSeconds = 0.0;
    for (const Format& format : formats) {
        const std::string path =
            (fs::temp_directory_path() /
             ("depthcloud-bench-" + std::to_string(::getpid()) + "-formats" + format.extension))
                .string();
        const Status written = format.write(path, frames);
        auto source = written ? devices::replay::openReplaySource(path)
                              : Expected<std::unique_ptr<devices::replay::ReplaySource>>(written.error());
        if (!source) {
            std::printf("  %-44s cannot write or open: %s\n", format.name, source.error().message.c_str());
        } else {
            const double seconds = decodeAll(format.name, **source, true, passes);
            if (recordingSeconds == 0.0)
                recordingSeconds = seconds;
            else
                std::printf("  %-44s %.2fx the recording's time per frame\n", "", seconds / recordingSeconds);
        }
        std::error_code ec;
        fs::remove(path, ec);
    }
}

} // namespace dc::tool
