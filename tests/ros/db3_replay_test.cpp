// rosbag2 sqlite3 recordings (`replay:DIR` whose metadata.yaml says sqlite3): a .db3 written by an
// independent helper (make_test_db3.py: Python's sqlite3 and its own CDR packing) replayed pixel for pixel,
// stamp for stamp and with its camera_info; broken folders and files are one-line errors.

#include "devices/recording/frame_codec.h"
#include "devices/replay/replay_spec.h"
#include "devices/ros/bag_source.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/replay_test_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <utility>

namespace dc::devices::ros {
namespace {

namespace fs = std::filesystem;
using namespace pattern;

class Db3Replay : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir;
        for (const auto& [folder, arguments] :
             {std::pair{bag(), "1"}, std::pair{split(), "2"}, std::pair{compressed(), "1 compressed"}}) {
            const std::string command =
                std::string("/usr/bin/python3 ") + DC_DB3_WRITER_SCRIPT + " " + folder + " " + arguments;
            if (std::system(command.c_str()) != 0)
                problem_ = "the .db3 writer failed (" + command + ")";
        }
    }
    static void TearDownTestSuite() { delete dir_; }
    void SetUp() override { ASSERT_TRUE(problem_.empty()) << problem_; }
    static std::string bag() { return dir_->path("bag"); }
    static std::string split() { return dir_->path("split"); } // the same frames in two .db3 files
    // The same frames as image_transport's compressedDepth and compressed (PNG) topics.
    static std::string compressed() { return dir_->path("compressed"); }

    static inline test::TempDir* dir_ = nullptr;
    static inline std::string problem_;
};

// Opens `spec` and checks every frame against the writer's pattern, last to first (seeks included).
void expectEveryFrameAsWritten(const std::string& spec) {
    auto source = replay::openReplaySpecSource(spec);
    ASSERT_TRUE(source) << source.error().message;
    ASSERT_EQ((*source)->frameCount(), kFrames);
    EXPECT_NE((*source)->description().find("/camera/camera/depth/image_rect_raw"), std::string::npos);
    for (std::size_t i = kFrames; i-- > 0;) {
        auto f = (*source)->frame(i);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(f->timestampNs, kStartNs + static_cast<std::int64_t>(i) * kFrameNs); // the stamp
        const auto& d = f->sceneDepth->depthMeters;
        ASSERT_EQ(d.width, kDepthW);
        ASSERT_EQ(d.height, kDepthH);
        for (int y = 0; y < kDepthH; ++y)
            for (int x = 0; x < kDepthW; ++x)
                ASSERT_EQ(d.at(x, y), recording::depthFromUnits(depthUnits(x, y, i), 0.001))
                    << "frame " << i << " at " << x << "," << y;
        ASSERT_EQ(f->capturedImage.width, kColorW);
        ASSERT_EQ(f->capturedImage.format, frame::PixelFormat::Rgb24);
        for (int y = 0; y < kColorH; ++y)
            for (int x = 0; x < kColorW; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ((*f->capturedImage.bytes)[(y * kColorW + x) * 3 + c], colorRgb(x, y, i)[c]);
    }
    const BagRig* rig = bagRig(**source);
    ASSERT_TRUE(rig && rig->depth && rig->color);
    EXPECT_EQ(rig->depth->intrinsics.fx, 50.0);
    EXPECT_EQ(rig->depth->intrinsics.fy, 51.0);
    EXPECT_EQ(rig->color->intrinsics.cx, 40.0);
    EXPECT_EQ(rig->depth->distortion, (std::vector<double>{0.1, -0.2, 0.001, 0.002, 0.05}));
    EXPECT_TRUE((*source)->warnings().empty());
    // The colour camera's place comes from /tf_static alone: both optical frames hang on camera_link, the
    // colour one 30 mm further along y.
    ASSERT_TRUE(rig->depthToColor);
    EXPECT_EQ(rig->depthToColor->rotation, (std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
    EXPECT_NEAR(rig->depthToColor->translationMeters[0], 0.0, 1e-12);
    EXPECT_NEAR(rig->depthToColor->translationMeters[1], 0.03, 1e-12);
    EXPECT_NEAR(rig->depthToColor->translationMeters[2], 0.0, 1e-12);
    // Each frame's pose is the depth frame's chain: camera_link's /tf transform (make_test_db3.py's pose(i),
    // not the decoy's) after the fixed 15 mm along y.
    EXPECT_TRUE((*source)->capabilities().pose);
    for (std::size_t i = 0; i < kFrames; ++i) {
        auto f = (*source)->frame(i);
        ASSERT_TRUE(f && f->pose) << "frame " << i;
        const auto& m = f->pose->cameraToWorld;
        const double angle = 0.1 * static_cast<double>(i);
        EXPECT_NEAR(m[0], std::cos(angle), 1e-12);
        EXPECT_NEAR(m[1], std::sin(angle), 1e-12);
        EXPECT_NEAR(m[4], -std::sin(angle), 1e-12);
        EXPECT_NEAR(m[10], 1.0, 1e-12);
        EXPECT_NEAR(m[12], 0.1 * static_cast<double>(i) - 0.015 * std::sin(angle), 1e-12);
        EXPECT_NEAR(m[13], 0.2 + 0.015 * std::cos(angle), 1e-12);
        EXPECT_NEAR(m[14], 0.3, 1e-12);
    }
}

TEST_F(Db3Replay, EveryFrameEqualsWhatWasWrittenWithItsStampAndCalibration) {
    expectEveryFrameAsWritten("replay:" + bag());
}

TEST_F(Db3Replay, CompressedTopicsReplayAsTheirRawImagesWould) {
    expectEveryFrameAsWritten("replay:" + compressed());
}

TEST_F(Db3Replay, TheDb3FileAloneReplaysWithoutItsFolder) {
    const std::string alone = dir_->path("alone.db3");
    fs::copy_file(bag() + "/rosbag2_0.db3", alone);
    expectEveryFrameAsWritten("replay:" + alone);
    EXPECT_EQ(replay::classifyCapture(alone), replay::CaptureKind::Rosbag2);
    const std::string renamed = dir_->path("recording.sqlite");
    fs::copy_file(alone, renamed);
    EXPECT_EQ(replay::classifyCapture(renamed), replay::CaptureKind::Rosbag2) << "known by its header";
    expectEveryFrameAsWritten("replay:" + renamed);
}

// The second file numbers the topics apart from the first; the frames run on across the split.
TEST_F(Db3Replay, AFolderSplitOverTwoFilesReplaysAsOneRecording) {
    ASSERT_TRUE(fs::exists(split() + "/rosbag2_1.db3"));
    expectEveryFrameAsWritten("replay:" + split());
}

// One file of a split recording replays alone (it may be all the person has), with a warning naming the
// recording it belongs to; the folder, or a file of an unsplit one, has no such warning.
TEST_F(Db3Replay, OneFileOfASplitRecordingSaysWhereTheRestIs) {
    auto part = replay::openReplaySpecSource("replay:" + split() + "/rosbag2_1.db3");
    ASSERT_TRUE(part) << part.error().message;
    EXPECT_GT((*part)->frameCount(), 0u);
    EXPECT_LT((*part)->frameCount(), kFrames);
    const auto warnings = (*part)->warnings();
    const std::string expected =
        "is file 2 of 2 of the recording in " + split() + ", which replay:" + split();
    EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) {
        return w.find(expected) != std::string::npos;
    })) << (warnings.empty() ? "no warning" : warnings.front());
    auto mentionsParts = [](const replay::ReplaySource& s) {
        const auto all = s.warnings();
        return std::any_of(all.begin(), all.end(), [](const std::string& w) {
            return w.find("of the recording in") != std::string::npos;
        });
    };
    auto whole = replay::openReplaySpecSource("replay:" + split());
    ASSERT_TRUE(whole) << whole.error().message;
    EXPECT_FALSE(mentionsParts(**whole));
    auto unsplit = replay::openReplaySpecSource("replay:" + bag() + "/rosbag2_0.db3");
    ASSERT_TRUE(unsplit) << unsplit.error().message;
    EXPECT_FALSE(mentionsParts(**unsplit));
}

TEST_F(Db3Replay, AListedFileThatIsMissingIsNamed) {
    const std::string cut = dir_->path("cut");
    fs::create_directories(cut);
    fs::copy_file(split() + "/metadata.yaml", cut + "/metadata.yaml");
    fs::copy_file(split() + "/rosbag2_0.db3", cut + "/rosbag2_0.db3");
    auto source = replay::openReplaySpecSource("replay:" + cut);
    ASSERT_FALSE(source);
    EXPECT_NE(source.error().message.find("rosbag2_1.db3"), std::string::npos) << source.error().message;
}

TEST_F(Db3Replay, BrokenFoldersAndFilesAreOneLineErrors) {
    const std::string empty = dir_->path("empty");
    fs::create_directories(empty);
    std::ofstream(empty + "/metadata.yaml")
        << "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n";
    auto none = replay::openReplaySpecSource("replay:" + empty);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("0 .db3 files"), std::string::npos) << none.error().message;

    std::ofstream(empty + "/garbage.db3") << "this is not an sqlite database, just text of some length......";
    auto garbage = replay::openReplaySpecSource("replay:" + empty);
    ASSERT_FALSE(garbage);
    EXPECT_NE(garbage.error().message.find("garbage.db3"), std::string::npos) << garbage.error().message;
    EXPECT_EQ(garbage.error().message.find('\n'), std::string::npos);
}

} // namespace
} // namespace dc::devices::ros
