// `depthcloud export --format mcap`: a recording written as ROS 2 messages in MCAP, read back by readers
// that are not ours (tests/mcap/writer/read_mcap.js: Foxglove's @mcap/core stream and indexed readers, each
// message decoded through its own schema by Foxglove's ros2msg parser and CDR reader) and by our own
// replay; compared with the source frames pixel for pixel and stamp for stamp.

#include "devices/recording/frame_codec.h"
#include "devices/replay/replay_source.h"
#include "devices/replay/replay_spec.h"
#include "devices/synthetic/synthetic_device.h"
#include "exporting/export.h"
#include "exporting/mcap_export.h"
#include "frame/camera_model.h"
#include "frame/rgb_image.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/shell_run.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sys/wait.h>

namespace dc::exporting {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::readText;
using test::runIn;
using test::RunResult;

constexpr int kFrames = 4;
constexpr int kTopics = 7; // depth, colour, infrared, their camera_info, /tf

std::vector<std::uint8_t> base64(const std::string& text) {
    static const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<std::uint8_t> out;
    std::uint32_t bits = 0;
    int count = 0;
    for (const char c : text) {
        const auto at = kAlphabet.find(c);
        if (at == std::string::npos)
            continue; // '=' padding
        bits = (bits << 6) | static_cast<std::uint32_t>(at);
        if ((count += 6) >= 8) {
            count -= 8;
            out.push_back(static_cast<std::uint8_t>(bits >> count));
        }
    }
    return out;
}

template <class T> std::vector<T> valuesOf(const std::vector<std::uint8_t>& bytes) {
    std::vector<T> values(bytes.size() / sizeof(T));
    std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
    return values;
}

std::int64_t stampNs(const json& header) {
    return header["stamp"]["sec"].get<std::int64_t>() * 1'000'000'000 +
           header["stamp"]["nanosec"].get<std::int64_t>();
}

class McapExport : public ::testing::Test {
protected:
    // A recording of the moving synthetic camera (NV12 colour, pose) with an infrared image; `millimetres`
    // rounds its depth to whole millimetres (a RealSense's), else it keeps the synthetic float depth.
    std::string record(const std::string& name, bool millimetres) {
        auto frames = test::syntheticFrames(kFrames, 32, 24);
        for (std::size_t i = 0; i < frames.size(); ++i) {
            auto f = std::make_shared<frame::Frame>(*frames[i]);
            if (millimetres)
                for (float& d : f->sceneDepth->depthMeters.pixels)
                    d = d > 0.0f ? devices::recording::depthFromUnits(
                                       static_cast<std::uint16_t>(std::lround(d * 1000.0f)), 0.001)
                                 : 0.0f;
            // 8-bit values in even frames, 16-bit in odd ones: mono8 and mono16 both.
            f->infrared = frame::Plane<std::uint16_t>(32, 24);
            for (std::size_t k = 0; k < f->infrared->pixels.size(); ++k)
                f->infrared->pixels[k] = static_cast<std::uint16_t>((k * 7 + i) % (i % 2 ? 4000 : 256));
            frames[i] = std::move(f);
        }
        const std::string path = dir_.path(name);
        test::writeRecording(path, frames);
        return path;
    }
    // The frames the export reads (the replay's, sanitised as export sanitises them).
    static std::vector<frame::Frame> framesOf(const std::string& spec) {
        auto source = devices::replay::openReplaySpecSource(spec);
        EXPECT_TRUE(source) << source.error().message;
        std::vector<frame::Frame> frames;
        for (std::size_t i = 0; source && i < (*source)->frameCount(); ++i) {
            auto f = devices::replay::loadFrame(**source, i);
            EXPECT_TRUE(f) << f.error().message;
            if (f)
                frames.push_back(std::move(*f));
        }
        return frames;
    }
    RunResult exportMcap(const std::string& source, const std::string& out, const std::string& extra = "") {
        return runIn(dir_.path(), std::string(DEPTHCLOUD_BINARY) + " export --format mcap --source replay:" +
                                      source + " --out " + out + " " + extra);
    }
    // What Foxglove's readers find in the file; fails the test when they cannot read it.
    json readBack(const std::string& file) {
        const RunResult r =
            runIn(dir_.path(), std::string(DC_NODE) + " " + DC_MCAP_READER_SCRIPT + " " + file);
        EXPECT_EQ(r.exitCode, 0) << r.err << " (run scripts/setup.sh for node and its packages)";
        return r.exitCode == 0 ? json::parse(r.out) : json::object();
    }
    void expectIndexedZstdSummary(const json& j);
    void expectFramesEqual(const json& j, const std::vector<frame::Frame>& frames, const char* depthEncoding);

    test::TempDir dir_;
};

void McapExport::expectIndexedZstdSummary(const json& j) {
    EXPECT_EQ(j["profile"], "ros2");
    const json& records = j["records"];
    const int chunks = records.value("Chunk", 0);
    ASSERT_GE(chunks, 1);
    EXPECT_EQ(records.value("ChunkIndex", 0), chunks);
    EXPECT_GE(records.value("MessageIndex", 0), chunks);
    EXPECT_EQ(records.value("DataEnd", 0), 1);
    EXPECT_EQ(records.value("Statistics", 0), 1);
    EXPECT_GE(records.value("SummaryOffset", 0), 3);
    EXPECT_EQ(records.value("Footer", 0), 1);
    EXPECT_EQ(records.value("Message", 0), kFrames * kTopics);
    for (const auto& compression : j["chunkCompressions"])
        EXPECT_EQ(compression, "zstd");
    EXPECT_EQ(j["summary"]["chunkIndexes"], chunks);
    EXPECT_EQ(j["summary"]["statistics"]["messageCount"], std::to_string(kFrames * kTopics));
    EXPECT_EQ(j["summary"]["statistics"]["chunkCount"], chunks);
    EXPECT_EQ(j["crcs"], (json{{"dataSection", true}, {"dataSectionStated", true}, {"summary", true}}));
    std::set<std::string> schemas, topics;
    for (const auto& s : j["schemas"]) {
        schemas.insert(s["name"].get<std::string>());
        EXPECT_EQ(s["encoding"], "ros2msg");
    }
    for (const auto& c : j["channels"]) {
        topics.insert(c["topic"].get<std::string>());
        EXPECT_EQ(c["messageEncoding"], "cdr");
    }
    EXPECT_EQ(schemas, (std::set<std::string>{"sensor_msgs/msg/Image", "sensor_msgs/msg/CameraInfo",
                                              "tf2_msgs/msg/TFMessage"}));
    const std::set<std::string> expected{"/camera/camera/depth/image_rect_raw",
                                         "/camera/camera/depth/camera_info",
                                         "/camera/camera/color/image_raw",
                                         "/camera/camera/color/camera_info",
                                         "/camera/camera/infra1/image_rect_raw",
                                         "/camera/camera/infra1/camera_info",
                                         "/tf"};
    EXPECT_EQ(topics, expected);
    for (const auto& topic : expected)
        EXPECT_EQ(j["messages"][topic].size(), static_cast<std::size_t>(kFrames)) << topic;
}

// Every message of every topic against the frame it came from.
void McapExport::expectFramesEqual(const json& j, const std::vector<frame::Frame>& frames,
                                   const char* depthEncoding) {
    ASSERT_EQ(frames.size(), static_cast<std::size_t>(kFrames));
    const json& m = j["messages"];
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const frame::Frame& f = frames[i];
        const json& depth = m["/camera/camera/depth/image_rect_raw"][i];
        EXPECT_EQ(depth["logTime"], std::to_string(f.timestampNs));
        const json& image = depth["message"];
        EXPECT_EQ(stampNs(image["header"]), f.timestampNs);
        const auto& d = f.sceneDepth->depthMeters;
        ASSERT_EQ(image["encoding"], depthEncoding);
        ASSERT_EQ(image["width"], d.width);
        ASSERT_EQ(image["height"], d.height);
        const auto bytes = base64(image["data"]);
        frame::Plane<float> decoded(d.width, d.height);
        if (std::string(depthEncoding) == "16UC1") {
            const auto units = valuesOf<std::uint16_t>(bytes);
            ASSERT_EQ(units.size(), d.pixels.size());
            for (std::size_t k = 0; k < units.size(); ++k)
                decoded.pixels[k] = devices::recording::depthFromUnits(units[k], 0.001);
        } else {
            decoded.pixels = valuesOf<float>(bytes);
        }
        EXPECT_TRUE(test::sameBits(decoded, d)) << "frame " << i;
        const json& color = m["/camera/camera/color/image_raw"][i]["message"];
        EXPECT_EQ(color["encoding"], "rgb8");
        EXPECT_EQ(stampNs(color["header"]), f.timestampNs);
        EXPECT_EQ(base64(color["data"]), frame::toRgb24(f.capturedImage)) << "frame " << i;
        const json& ir = m["/camera/camera/infra1/image_rect_raw"][i]["message"];
        const auto irBytes = base64(ir["data"]);
        const auto irValues = ir["encoding"] == "mono8"
                                  ? std::vector<std::uint16_t>(irBytes.begin(), irBytes.end())
                                  : valuesOf<std::uint16_t>(irBytes);
        EXPECT_EQ(ir["encoding"], i % 2 ? "mono16" : "mono8");
        EXPECT_EQ(irValues, f.infrared->pixels) << "frame " << i;
        const json& info = m["/camera/camera/depth/camera_info"][i]["message"];
        const frame::Intrinsics k = f.depthIntrinsics();
        EXPECT_EQ(info["k"], (std::vector<double>{k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}));
        EXPECT_EQ(stampNs(info["header"]), f.timestampNs);
        const json& tf = m["/tf"][i]["message"]["transforms"][0];
        const auto& pose = f.pose->cameraToWorld;
        EXPECT_EQ(tf["child_frame_id"], "camera_depth_optical_frame");
        EXPECT_EQ(tf["transform"]["translation"]["x"], pose[12]);
        EXPECT_EQ(tf["transform"]["translation"]["z"], pose[14]);
        // The quaternion turns back into the pose's rotation (column-major m[col * 4 + row]).
        const json& q = tf["transform"]["rotation"];
        const double x = q["x"], y = q["y"], z = q["z"], w = q["w"];
        EXPECT_NEAR(1 - 2 * (y * y + z * z), pose[0], 1e-9);
        EXPECT_NEAR(2 * (x * y - z * w), pose[4], 1e-9);
        EXPECT_NEAR(2 * (x * z + y * w), pose[8], 1e-9);
        EXPECT_NEAR(2 * (y * z - x * w), pose[9], 1e-9);
        EXPECT_NEAR(1 - 2 * (x * x + y * y), pose[10], 1e-9);
    }
}

TEST_F(McapExport, MillimetreDepthIs16UC1AndReadsBackThroughFoxglovesReaders) {
    const std::string recording = record("mm.dcrec", true);
    const RunResult r = exportMcap(recording, "out.mcap");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("wrote 4 frames as mcap"), std::string::npos) << r.out;
    const json j = readBack(dir_.path("out.mcap"));
    ASSERT_FALSE(j.empty());
    expectIndexedZstdSummary(j);
    expectFramesEqual(j, framesOf("replay:" + recording), "16UC1");
}

TEST_F(McapExport, FloatDepthIs32FC1BitForBit) {
    const std::string recording = record("float.dcrec", false);
    ASSERT_EQ(exportMcap(recording, "out.mcap").exitCode, 0);
    const json j = readBack(dir_.path("out.mcap"));
    ASSERT_FALSE(j.empty());
    expectIndexedZstdSummary(j);
    expectFramesEqual(j, framesOf("replay:" + recording), "32FC1");
}

// Our own MCAP replay reads the export back to the same depth, colour, infrared and stamps.
TEST_F(McapExport, ReplayOfTheExportGivesBackTheSameFrames) {
    for (const bool millimetres : {true, false}) {
        const std::string name = millimetres ? "mm" : "float";
        const std::string recording = record(name + ".dcrec", millimetres);
        ASSERT_EQ(exportMcap(recording, name + ".mcap").exitCode, 0);
        const auto source = framesOf("replay:" + recording);
        const auto replayed = framesOf("replay:" + dir_.path(name + ".mcap"));
        ASSERT_EQ(replayed.size(), source.size());
        for (std::size_t i = 0; i < source.size(); ++i) {
            EXPECT_EQ(replayed[i].timestampNs, source[i].timestampNs);
            EXPECT_TRUE(
                test::sameBits(replayed[i].sceneDepth->depthMeters, source[i].sceneDepth->depthMeters))
                << name << " frame " << i;
            EXPECT_EQ(frame::toRgb24(replayed[i].capturedImage), frame::toRgb24(source[i].capturedImage));
            ASSERT_TRUE(replayed[i].infrared);
            EXPECT_EQ(replayed[i].infrared->pixels, source[i].infrared->pixels);
            const frame::Intrinsics a = replayed[i].depthIntrinsics(), b = source[i].depthIntrinsics();
            EXPECT_NEAR(a.fx, b.fx, 1e-9);
            EXPECT_NEAR(a.cy, b.cy, 1e-9);
            // The pose comes back from /tf (odom -> camera_depth_optical_frame).
            ASSERT_TRUE(source[i].pose && replayed[i].pose) << name << " frame " << i;
            for (std::size_t e = 0; e < 16; ++e)
                EXPECT_NEAR(replayed[i].pose->cameraToWorld[e], source[i].pose->cameraToWorld[e], 1e-9)
                    << name << " frame " << i << " element " << e;
        }
    }
}

// A two-sensor frame's extrinsics go to /tf_static (the colour camera in the depth camera's frame) and come
// back as the replay's calibration, through tf alone.
TEST_F(McapExport, ATwoSensorRigsExtrinsicsGoToTfStaticAndComeBackAsItsCalibration) {
    devices::SyntheticConfig config;
    config.rig = true;
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open());
    const std::string path = dir_.path("rig.mcap");
    auto writer = McapFrameWriter::create(path, false);
    ASSERT_TRUE(writer) << writer.error().message;
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < 2; ++i) {
        frames.push_back(device.makeFrame(static_cast<std::uint64_t>(i), 1.0 + i / 30.0));
        ASSERT_TRUE((*writer)->add(*frames.back()));
    }
    ASSERT_TRUE((*writer)->finish());
    const frame::RigCalibration& want = *frames.front()->rig;
    ASSERT_FALSE(want.depthToColour.isIdentity()) << "a rig whose sensors sit apart";
    const auto replayed = framesOf("replay:" + path);
    ASSERT_EQ(replayed.size(), 2u);
    ASSERT_TRUE(replayed.front().rig) << "replayed as a two-sensor frame";
    const frame::RigidTransform& got = replayed.front().rig->depthToColour;
    for (std::size_t k = 0; k < 9; ++k)
        EXPECT_NEAR(got.rotation[k], want.depthToColour.rotation[k], 1e-9) << "rotation " << k;
    for (std::size_t k = 0; k < 3; ++k)
        EXPECT_NEAR(got.translationMeters[k], want.depthToColour.translationMeters[k], 1e-12) << "t " << k;
    // The lenses as the streams see them (the synthetic rig is calibrated at its native modes).
    const frame::Intrinsics& colour = frames.front()->cameraIntrinsics;
    const frame::Intrinsics depth = frames.front()->depthIntrinsics();
    EXPECT_NEAR(replayed.front().rig->colour.intrinsics.scaledTo(colour.width, colour.height).fx,
                want.colour.intrinsics.scaledTo(colour.width, colour.height).fx, 1e-9);
    EXPECT_NEAR(replayed.front().rig->depth.intrinsics.scaledTo(depth.width, depth.height).cx,
                want.depth.intrinsics.scaledTo(depth.width, depth.height).cx, 1e-9);
}

TEST_F(McapExport, AnExistingFileIsRefusedWithoutOverwriteAndReplacedWithIt) {
    const std::string recording = record("mm.dcrec", true);
    const std::vector<std::uint8_t> precious{'k', 'e', 'e', 'p'};
    test::writeBytes(dir_.path("out.mcap"), precious);
    const RunResult refused = exportMcap(recording, "out.mcap");
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    EXPECT_NE(refused.err.find("--out"), std::string::npos) << refused.err;
    EXPECT_EQ(test::readBytes(dir_.path("out.mcap")), precious);

    const RunResult replaced = exportMcap(recording, "out.mcap", "--overwrite");
    ASSERT_EQ(replaced.exitCode, 0) << replaced.err;
    EXPECT_EQ(readBack(dir_.path("out.mcap"))["summary"]["statistics"]["messageCount"],
              std::to_string(kFrames * kTopics));

    fs::create_directory(dir_.path("folder"));
    const RunResult directory = exportMcap(recording, "folder", "--overwrite");
    EXPECT_EQ(directory.exitCode, 2);
    EXPECT_NE(directory.err.find("--out"), std::string::npos) << directory.err;
}

// A cancelled (or failed) export leaves neither the file nor its temporary beside it.
TEST_F(McapExport, ACancelledExportLeavesNoFile) {
    const std::string recording = record("mm.dcrec", true);
    auto source = devices::replay::openReplaySpecSource("replay:" + recording);
    ASSERT_TRUE(source) << source.error().message;
    ExportOptions options;
    options.format = ExportFormat::Mcap;
    options.outDirectory = dir_.path("out/cancelled.mcap");
    auto result = exportFrames(**source, options, [](std::size_t done, std::size_t) { return done < 2; });
    EXPECT_FALSE(result);
    ASSERT_TRUE(fs::is_directory(dir_.path("out")));
    EXPECT_TRUE(fs::is_empty(dir_.path("out")));
}

// `record` to a .mcap: the take is recorded, converted, and only the MCAP remains.
TEST_F(McapExport, RecordToMcapLeavesOneIndexedFile) {
    const RunResult r = runIn(dir_.path(), std::string(DEPTHCLOUD_BINARY) +
                                               " record --source synthetic --frames 5 take.mcap");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir_.path("take.mcap.dcrec")));
    const json j = readBack(dir_.path("take.mcap"));
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j["summary"]["chunkIndexCompressions"][0], "zstd");
    EXPECT_EQ(j["messages"]["/camera/camera/depth/image_rect_raw"].size(), 5u);
    EXPECT_EQ(j["messages"]["/camera/camera/color/image_raw"].size(), 5u);

    const RunResult again = runIn(dir_.path(), std::string(DEPTHCLOUD_BINARY) +
                                                   " record --source synthetic --frames 5 take.mcap");
    EXPECT_EQ(again.exitCode, 2);
    EXPECT_NE(again.err.find("take.mcap already exists"), std::string::npos) << again.err;
}

} // namespace
} // namespace dc::exporting
