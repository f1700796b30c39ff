// ROS 2 recordings: MCAP files written by an independent writer (Foxglove's @mcap/core and @foxglove/cdr,
// tests/mcap/writer) in a ROS 2 RealSense wrapper's layout, replayed through the replay machinery pixel for
// pixel: every chunk compression, with and without summary and indexes, big-endian CDR, a rosbag2 folder, a
// file cut short, and broken input.

#include "devices/recording/frame_codec.h"
#include "devices/replay/replay_spec.h"
#include "devices/ros/bag_source.h"
#include "devices/ros/mcap_reader.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/replay_test_pattern.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>

namespace dc::devices::ros {
namespace {

namespace fs = std::filesystem;
using replay::ReplaySource;

using namespace pattern; // the writers' layout and formulas

std::uint16_t infraredValue(int x, int y, std::size_t i) {
    return static_cast<std::uint16_t>((x * 7 + y * 3 + static_cast<int>(i)) & 0xff);
}

// One file the writer makes, and what it holds beyond 16UC1 depth and colour.
struct Layout {
    const char* file;
    bool floatDepth = false; // 32FC1 metres
    bool infrared = false;   // an infra1 mono8 stream
};

// Test names (and CTest's) show the file, not the struct's bytes.
void PrintTo(const Layout& layout, std::ostream* out) {
    *out << layout.file;
}

class McapReplay : public ::testing::TestWithParam<Layout> {
protected:
    // CTest writes the files once (the McapTestFiles fixture); a run of the binary alone writes them itself.
    // Without node or its packages (scripts/setup.sh installs both) every test here fails rather than skips.
    static void SetUpTestSuite() {
        if (fs::exists(file("zstd.mcap")))
            return;
        const std::string command = std::string(DC_NODE) + " " + DC_MCAP_WRITER_SCRIPT + " " + kDirectory;
        if (std::system(command.c_str()) != 0)
            problem_ = "the MCAP writer failed (" + command + "): run scripts/setup.sh";
    }
    void SetUp() override { ASSERT_TRUE(problem_.empty()) << problem_; }
    static constexpr const char* kDirectory = DC_TEST_MCAP_DIRECTORY;
    static std::string file(const std::string& name) { return std::string(kDirectory) + "/" + name; }
    static std::unique_ptr<ReplaySource> open(const std::string& spec) {
        auto source = replay::openReplaySpecSource(spec);
        EXPECT_TRUE(source) << source.error().message;
        return source ? std::move(*source) : nullptr;
    }
    static void expectFrame(ReplaySource& source, std::size_t i, const Layout& layout = {}) {
        auto f = source.frame(i);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(f->timestampNs,
                  kStartNs + static_cast<std::int64_t>(i) * kFrameNs); // the stamp, not log time
        ASSERT_TRUE(f->sceneDepth);
        const auto& d = f->sceneDepth->depthMeters;
        ASSERT_EQ(d.width, kDepthW);
        ASSERT_EQ(d.height, kDepthH);
        for (int y = 0; y < kDepthH; ++y)
            for (int x = 0; x < kDepthW; ++x)
                ASSERT_EQ(d.at(x, y), layout.floatDepth
                                          ? static_cast<float>(depthUnits(x, y, i) / 1000.0)
                                          : recording::depthFromUnits(depthUnits(x, y, i), 0.001))
                    << "frame " << i << " at " << x << "," << y;
        ASSERT_EQ(f->capturedImage.format, frame::PixelFormat::Rgb24);
        ASSERT_EQ(f->capturedImage.width, kColorW);
        ASSERT_EQ(f->capturedImage.height, kColorH);
        for (int y = 0; y < kColorH; ++y)
            for (int x = 0; x < kColorW; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ((*f->capturedImage.bytes)[(y * kColorW + x) * 3 + c], colorRgb(x, y, i)[c])
                        << "frame " << i << " at " << x << "," << y;
        ASSERT_EQ(f->infrared.has_value(), layout.infrared);
        if (!layout.infrared)
            return;
        ASSERT_EQ(f->infrared->width, kDepthW);
        for (int y = 0; y < kDepthH; ++y)
            for (int x = 0; x < kDepthW; ++x)
                ASSERT_EQ(f->infrared->at(x, y), infraredValue(x, y, i))
                    << "frame " << i << " at " << x << "," << y;
    }
    static inline std::string problem_;
};

TEST_P(McapReplay, EveryFrameEqualsWhatWasWrittenWithItsStamp) {
    auto source = open("replay:" + file(GetParam().file));
    ASSERT_TRUE(source);
    ASSERT_EQ(source->frameCount(), kFrames);
    EXPECT_TRUE(source->capabilities().color);
    EXPECT_NE(source->description().find("/camera/camera/depth/image_rect_raw"), std::string::npos);
    // Backwards: each read seeks through the index, across chunks, rather than following the file.
    for (std::size_t i = kFrames; i-- > 0;) {
        EXPECT_EQ(source->timestampNs(i), kStartNs + static_cast<std::int64_t>(i) * kFrameNs);
        expectFrame(*source, i, GetParam());
    }
    if (GetParam().infrared) {
        EXPECT_NE(source->description().find("infrared /camera/camera/infra1/image_rect_raw"),
                  std::string::npos);
    }
    EXPECT_TRUE(source->warnings().empty()) << source->warnings().front();
}

TEST_P(McapReplay, CalibrationComesFromCameraInfo) {
    auto source = open("replay:" + file(GetParam().file));
    ASSERT_TRUE(source);
    EXPECT_FALSE(source->capabilities().approximateIntrinsics);
    const BagRig* rig = bagRig(*source);
    ASSERT_NE(rig, nullptr);
    ASSERT_TRUE(rig->depth && rig->color);
    EXPECT_EQ(rig->depth->intrinsics.fx, 50.0);
    EXPECT_EQ(rig->depth->intrinsics.fy, 51.0);
    EXPECT_EQ(rig->depth->intrinsics.cx, 32.0);
    EXPECT_EQ(rig->depth->intrinsics.cy, 24.0);
    EXPECT_EQ(rig->depth->distortionModel, "plumb_bob");
    EXPECT_EQ(rig->depth->distortion, (std::vector<double>{0.1, -0.2, 0.001, 0.002, 0.05}));
    EXPECT_EQ(rig->color->intrinsics.fx, 60.0);
    EXPECT_EQ(rig->color->intrinsics.cy, 30.0);
    EXPECT_EQ(rig->color->distortionModel, "rational_polynomial");
    EXPECT_EQ(rig->color->distortion.size(), 8u);
    // Without the depth -> colour transform (ROS 2 keeps it in tf), colour is taken as one camera's: the
    // depth camera's intrinsics at the colour image's size.
    auto f = source->frame(0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->cameraIntrinsics.fx, 50.0 * kColorW / kDepthW);
}

INSTANTIATE_TEST_SUITE_P(Layouts, McapReplay,
                         ::testing::Values(Layout{"zstd.mcap"}, Layout{"lz4.mcap"},
                                           Layout{"uncompressed-chunks.mcap"}, Layout{"unchunked.mcap"},
                                           Layout{"no-summary.mcap"}, Layout{"no-message-index.mcap"},
                                           Layout{"big-endian.mcap"}, Layout{"rosbag2"},
                                           Layout{"float-bgr.mcap", true},
                                           Layout{"rgba-infrared.mcap", false, true},
                                           Layout{"bgra-big-endian.mcap", true}, Layout{"compressed.mcap"}),
                         [](const auto& info) {
                             std::string name = info.param.file;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c)))
                                     c = '_';
                             return name;
                         });

using McapFiles = McapReplay;

TEST_F(McapFiles, ACutFileReplaysUpToTheCut) {
    auto source = open("replay:" + file("truncated.mcap"));
    ASSERT_TRUE(source);
    ASSERT_EQ(source->frameCount(), 3u); // cut inside frame 3's chunk
    for (std::size_t i = 0; i < 3; ++i)
        expectFrame(*source, i);
    const auto warnings = source->warnings();
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings.front().find("cut short"), std::string::npos) << warnings.front();
}

// Each layout is read the way it was meant: an indexed file through its summary, the others by a pass.
TEST_F(McapFiles, IndexedFromTheSummaryWhereTheFileHasOne) {
    const std::pair<const char*, bool> layouts[] = {
        {"zstd.mcap", true},       {"lz4.mcap", true},         {"no-message-index.mcap", true},
        {"unchunked.mcap", false}, {"no-summary.mcap", false}, {"truncated.mcap", false}};
    for (const auto& [name, indexed] : layouts) {
        auto mcap = McapReader::open(file(name));
        ASSERT_TRUE(mcap) << mcap.error().message;
        EXPECT_EQ((*mcap)->readFromSummary(), indexed) << name;
        ASSERT_EQ((*mcap)->channels().size(), 4u) << name;
        const McapChannel& depth = (*mcap)->channels().front();
        EXPECT_EQ(depth.topic, "/camera/camera/depth/image_rect_raw");
        EXPECT_EQ(depth.schemaName, "sensor_msgs/msg/Image");
        EXPECT_EQ((*mcap)->messageCount(depth.id), std::string(name) == "truncated.mcap" ? 3u : kFrames)
            << name;
    }
}

TEST_F(McapFiles, ADepthTopicAloneReplaysWithoutColour) {
    auto source = open("replay:" + file("zstd.mcap") + ":topics=/camera/camera/depth/image_rect_raw");
    ASSERT_TRUE(source);
    EXPECT_FALSE(source->capabilities().color);
    auto f = source->frame(2);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->capturedImage.width, 0);
    auto wrong = replay::openReplaySpecSource("replay:" + file("zstd.mcap") +
                                              ":topics=/camera/camera/color/image_raw");
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.error().message.find("not a depth image"), std::string::npos) << wrong.error().message;
}

TEST_F(McapFiles, ClassifiedByMagicOrExtensionInAnyCase) {
    test::TempDir dir;
    std::ofstream(dir.path("X.MCAP")) << "not yet an mcap";
    fs::copy_file(file("zstd.mcap"), dir.path("renamed.bin"));
    EXPECT_EQ(replay::classifyCapture(dir.path("X.MCAP")), replay::CaptureKind::Mcap);
    EXPECT_EQ(replay::classifyCapture(dir.path("renamed.bin")), replay::CaptureKind::Mcap);
    EXPECT_EQ(replay::classifyCapture(file("rosbag2")), replay::CaptureKind::Rosbag2);
    auto renamed = open("replay:" + dir.path("renamed.bin"));
    ASSERT_TRUE(renamed);
    EXPECT_EQ(renamed->frameCount(), kFrames);
}

// Broken input is a one-line error naming the file, never a crash or a hang.
TEST_F(McapFiles, BrokenInputIsOneLineError) {
    test::TempDir dir;
    std::ofstream(dir.path("garbage.mcap")) << "this is not an MCAP file at all";
    std::string bytes;
    {
        std::ifstream in(file("zstd.mcap"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::ofstream(dir.path("header-only.mcap"), std::ios::binary) << bytes.substr(0, 40);
    std::string flipped = bytes;
    for (std::size_t i = 200; i < flipped.size() - 2000; i += 97) // damage the chunks, keep the summary
        flipped[i] = static_cast<char>(flipped[i] ^ 0x5a);
    std::ofstream(dir.path("damaged.mcap"), std::ios::binary) << flipped;
    fs::create_directories(dir.path("sqlite"));
    std::ofstream(dir.path("sqlite/metadata.yaml"))
        << "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n";
    for (const char* name : {"garbage.mcap", "header-only.mcap", "sqlite"}) {
        auto source = replay::openReplaySpecSource("replay:" + dir.path(name));
        ASSERT_FALSE(source) << name;
        EXPECT_EQ(source.error().message.find('\n'), std::string::npos) << source.error().message;
        EXPECT_NE(source.error().message.find(dir.path(name)), std::string::npos) << source.error().message;
    }
    // A damaged chunk fails the frames in it, with a message; it never crashes.
    auto damaged = replay::openReplaySpecSource("replay:" + dir.path("damaged.mcap"));
    if (!damaged) {
        EXPECT_EQ(damaged.error().message.find('\n'), std::string::npos) << damaged.error().message;
        return;
    }
    for (std::size_t i = 0; i < (*damaged)->frameCount(); ++i) {
        auto f = (*damaged)->frame(i);
        EXPECT_TRUE(f || f.error().message.find('\n') == std::string::npos) << f.error().message;
    }
}

} // namespace
} // namespace dc::devices::ros
