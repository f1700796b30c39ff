// Importers: the real ARKit capture in Stray layout, a TUM RGB-D frame, calibration override, and every
// broken capture directory the issue lists.

#include "devices/recording/format.h"
#include "devices/recording/frame_codec.h"
#include "devices/replay/importers.h"
#include "devices/replay/replay_source.h"
#include "devices/replay/stray_format.h"
#include "devices/replay/tum_format.h"
#include "exporting/export.h"
#include "frame/camera_model.h"
#include "tests/pose_checks.h"
#include "tests/recording/recording_test_support.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <unistd.h>
#include <vector>

namespace dc::devices::replay {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

const std::string kStray = test::dataPath("arkit_dance_stray");
const std::string kTum = test::dataPath("tum_frame");

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
}

TEST(StrayImport, RealArkitCaptureHasItsFramesSizesIntrinsicsPixelsAndPoses) {
    auto source = openReplaySource(kStray);
    ASSERT_TRUE(source) << source.error().message;
    ASSERT_EQ((*source)->frameCount(), 626u);
    const Capabilities caps = (*source)->capabilities();
    EXPECT_TRUE(caps.sceneDepth && caps.confidence && caps.color && caps.pose);
    EXPECT_EQ((*source)->timestampNs(300), 10'000'000'000);

    auto f0 = loadFrame(**source, 0);
    ASSERT_TRUE(f0) << f0.error().message;
    // Portrait, read from the files: 192 wide, 256 tall depth; 720x960 video.
    EXPECT_EQ(f0->sceneDepth->depthMeters.width, 192);
    EXPECT_EQ(f0->sceneDepth->depthMeters.height, 256);
    EXPECT_EQ(f0->capturedImage.width, 720);
    EXPECT_EQ(f0->capturedImage.height, 960);
    EXPECT_DOUBLE_EQ(f0->cameraIntrinsics.fx, 717.0636596679688);
    EXPECT_DOUBLE_EQ(f0->cameraIntrinsics.cy, 485.18304443359375);
    const frame::Intrinsics depthK = f0->depthIntrinsics();
    EXPECT_DOUBLE_EQ(depthK.fx, 717.0636596679688 * 192.0 / 720.0);
    EXPECT_DOUBLE_EQ(depthK.cy, 485.18304443359375 * 256.0 / 960.0);
    EXPECT_EQ(f0->sceneDepth->depthMeters.at(96, 128), recording::depthFromUnits(3283, 0.001));
    EXPECT_EQ(f0->sceneDepth->confidence.at(96, 128), 1);

    struct Known {
        std::size_t frame;
        int x, y;
        std::uint16_t millimetres;
        std::uint8_t confidence;
    };
    for (const Known k :
         {Known{313, 50, 200, 2350, 1}, Known{625, 10, 10, 2229, 2}, Known{100, 150, 30, 1989, 2}}) {
        auto f = loadFrame(**source, k.frame);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_FLOAT_EQ(f->sceneDepth->depthMeters.at(k.x, k.y), k.millimetres / 1000.0f) << k.frame;
        EXPECT_EQ(f->sceneDepth->confidence.at(k.x, k.y), k.confidence) << k.frame;
        EXPECT_EQ(f->replay, std::nullopt) << "only the replay device sets the position";
    }

    // odometry.csv row 300: t = (-0.654292464, -0.353809983, -0.403286695),
    // q = (-0.999892203, 0.009902398, -0.003212839, 0.010353851): nearly a half turn about x.
    auto f300 = loadFrame(**source, 300);
    ASSERT_TRUE(f300 && f300->pose);
    const auto& m = f300->pose->cameraToWorld;
    EXPECT_DOUBLE_EQ(m[12], -0.654292464);
    EXPECT_DOUBLE_EQ(m[13], -0.353809983);
    EXPECT_DOUBLE_EQ(m[14], -0.403286695);
    EXPECT_NEAR(m[0], 0.99978, 1e-4);   // 1 - 2(qy^2 + qz^2)
    EXPECT_NEAR(m[5], -0.99959, 1e-4);  // 1 - 2(qx^2 + qz^2)
    EXPECT_NEAR(m[10], -0.99976, 1e-4); // 1 - 2(qx^2 + qy^2)
}

TEST(StrayImport, EveryPoseOfTheRealCaptureIsRigid) {
    auto source = openReplaySource(kStray);
    ASSERT_TRUE(source) << source.error().message;
    (*source)->setDecodeColor(false); // poses only: no need to decode the video
    for (std::size_t i = 0; i < (*source)->frameCount(); ++i) {
        auto f = loadFrame(**source, i);
        ASSERT_TRUE(f && f->pose) << i;
        ASSERT_TRUE(test::isRigid(*f->pose)) << "frame " << i;
    }
}

TEST(StrayImport, SeekingTheVideoGivesTheSameImageAsReadingOn) {
    auto source = openStraySource(kStray);
    ASSERT_TRUE(source);
    auto sequential = (*source)->frame(41);
    auto back = (*source)->frame(3);   // backwards: a seek
    auto far = (*source)->frame(400);  // far ahead: a seek
    auto again = (*source)->frame(41); // backwards again
    ASSERT_TRUE(sequential && back && far && again);
    EXPECT_EQ(*sequential->capturedImage.bytes, *again->capturedImage.bytes);
    EXPECT_NE(*back->capturedImage.bytes, *far->capturedImage.bytes);
}

// A small Stray capture (8 synthetic frames written by our exporter), which each test breaks in one way.
class BrokenStray : public ::testing::Test {
protected:
    static constexpr std::size_t kFrames = 8;
    void SetUp() override {
        test::writeRecording(dir_.path("r.dcrec"), test::syntheticFrames(kFrames));
        auto recording = openRecordingSource(dir_.path("r.dcrec"));
        ASSERT_TRUE(recording);
        auto written = exporting::exportFrames(
            **recording, {exporting::ExportFormat::Stray, dir_.path("s"), {}, false, {}});
        ASSERT_TRUE(written) << written.error().message;
    }
    std::string path(const std::string& name) const { return dir_.path("s/" + name); }
    std::string openError() {
        auto source = openReplaySource(dir_.path("s"));
        return source ? "" : source.error().message;
    }
    TempDir dir_;
};

TEST_F(BrokenStray, IntactCopyOpens) {
    EXPECT_EQ(openError(), "");
}

TEST_F(BrokenStray, MissingDepthFileIsNamed) {
    fs::remove(path("depth/000005.png"));
    const std::string e = openError();
    EXPECT_NE(e.find("depth/000005.png is missing"), std::string::npos) << e;
}

TEST_F(BrokenStray, MissingVideoIsNamed) {
    fs::remove(path("rgb.mp4"));
    const std::string e = openError();
    EXPECT_NE(e.find("rgb.mp4 is missing"), std::string::npos) << e;
}

TEST_F(BrokenStray, DepthAndConfidenceCountsMustAgree) {
    fs::remove(path("confidence/000007.png"));
    const std::string e = openError();
    EXPECT_NE(e.find("mismatched frame counts: depth/ has 8 frames, confidence/ has 7"), std::string::npos)
        << e;
}

TEST_F(BrokenStray, DepthAndVideoCountsMustAgree) {
    fs::remove(path("depth/000007.png"));
    fs::remove(path("confidence/000007.png"));
    std::ifstream in(path("odometry.csv"));
    std::string text, line;
    for (std::size_t i = 0; i < kFrames && std::getline(in, line); ++i) // header + 7 rows
        text += line + "\n";
    writeText(path("odometry.csv"), text);
    const std::string e = openError();
    EXPECT_NE(e.find("depth/ has 7 frames, rgb.mp4 has 8"), std::string::npos) << e;
}

TEST_F(BrokenStray, UnreadableVideoIsAnError) {
    fs::remove(path("rgb.mp4"));
    writeText(path("rgb.mp4"), "this is not an mp4 file");
    const std::string e = openError();
    EXPECT_NE(e.find("rgb.mp4 (unreadable video)"), std::string::npos) << e;
}

TEST_F(BrokenStray, CaptureWithoutConfidenceSaysSo) {
    fs::remove_all(path("confidence"));
    auto source = openReplaySource(dir_.path("s"));
    ASSERT_TRUE(source) << source.error().message;
    EXPECT_FALSE((*source)->capabilities().confidence);
    EXPECT_TRUE((*source)->capabilities().sceneDepth);
    auto f = loadFrame(**source, 0);
    ASSERT_TRUE(f);
    EXPECT_TRUE(f->sceneDepth->confidence.empty());
}

TEST_F(BrokenStray, ZeroFrameCaptureIsAnError) {
    fs::remove_all(path("depth"));
    fs::create_directories(path("depth"));
    const std::string e = openError();
    EXPECT_NE(e.find("holds no frames"), std::string::npos) << e;
}

TEST_F(BrokenStray, DepthFileThatIsNotADepthPngFailsThatFrameOnly) {
    fs::copy_file(path("confidence/000005.png"), path("depth/000005.png"),
                  fs::copy_options::overwrite_existing);
    auto source = openReplaySource(dir_.path("s"));
    ASSERT_TRUE(source);
    auto bad = loadFrame(**source, 5);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("frame 5"), std::string::npos) << bad.error().message;
    EXPECT_NE(bad.error().message.find("depth/000005.png: expected a 16-bit"), std::string::npos);
    EXPECT_TRUE(loadFrame(**source, 6));
}

TEST(StrayFormat, TextErrorsNameFileLineAndByteOffset) {
    auto matrix = parseStrayCameraMatrix("1,0,2\n0,x,3\n0,0,1\n", "camera_matrix.csv");
    ASSERT_FALSE(matrix);
    EXPECT_EQ(matrix.error().message, "camera_matrix.csv: line 2 (byte offset 6): 'x' is not a number");
    auto odometry =
        parseStrayOdometry("timestamp, frame, x, y, z, qx, qy, qz, qw\n0, 0, 0, 0, 0, 0, 0, 0, 1\n"
                           "0.03, 1, 0, 0, nan, 0, 0, 0, 1\n",
                           "odometry.csv");
    ASSERT_FALSE(odometry);
    EXPECT_NE(odometry.error().message.find("odometry.csv: line 3 (byte offset 68): field 5"),
              std::string::npos)
        << odometry.error().message;
    auto ok = parseStrayOdometry("0.5, 0, 1, 2, 3, 0, 0, 0, 1\n", "o.csv");
    ASSERT_TRUE(ok);
    ASSERT_EQ(ok->size(), 1u);
    EXPECT_EQ((*ok)[0].pose.cameraToWorld[13], 2.0);
    EXPECT_EQ((*ok)[0].pose.cameraToWorld[0], 1.0);
}

TEST(TumFormat, ListsSkipCommentsAndAssociationIsNearestOneToOne) {
    auto list =
        parseTumList("# color images\n# timestamp filename\n2.0 rgb/b.png\n1.0 rgb/a.png\n\n", "rgb.txt");
    ASSERT_TRUE(list) << list.error().message;
    ASSERT_EQ(list->size(), 2u);
    EXPECT_EQ((*list)[0].file, "rgb/a.png") << "sorted by time";
    auto bad = parseTumList("# ok\n1.0\n", "depth.txt");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message, "depth.txt: line 2 (byte offset 5): expected 'timestamp filename'");

    using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;
    EXPECT_EQ(associateByTimestamp({1.0, 2.0, 3.0}, {1.01, 1.015, 2.5, 3.0}, 0.02), (Pairs{{0, 0}, {2, 3}}));
    // Both depth images are near the one color image: the closer one gets it, the other none.
    EXPECT_EQ(associateByTimestamp({1.000, 1.012}, {1.010}, 0.02), (Pairs{{1, 0}}));
    EXPECT_TRUE(associateByTimestamp({1.0}, {1.5}, 0.02).empty());
}

// associate.py's rule, written out: every pair within the window, sorted stably by difference, taken
// greedily.
std::vector<std::pair<std::size_t, std::size_t>>
associateAllPairs(const std::vector<double>& a, const std::vector<double>& b, double window) {
    struct C {
        double d;
        std::size_t i, j;
    };
    std::vector<C> all;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j)
            if (b[j] >= a[i] - window && b[j] <= a[i] + window)
                all.push_back({std::abs(a[i] - b[j]), i, j});
    std::stable_sort(all.begin(), all.end(), [](const C& x, const C& y) { return x.d < y.d; });
    std::vector<bool> usedA(a.size()), usedB(b.size());
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (const C& c : all)
        if (!usedA[c.i] && !usedB[c.j]) {
            usedA[c.i] = usedB[c.j] = true;
            pairs.emplace_back(c.i, c.j);
        }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

TEST(TumFormat, AssociationEqualsTheGreedyRuleOverAllPairsIncludingRepeatedStamps) {
    std::mt19937 random(7);
    for (int trial = 0; trial < 300; ++trial) {
        // Stamps on a coarse grid so that equal stamps and equal differences are common.
        std::uniform_int_distribution<int> tick(0, 12), count(0, 14);
        auto stamps = [&] {
            std::vector<double> v(static_cast<std::size_t>(count(random)));
            for (double& t : v)
                t = 1.0 + 0.01 * tick(random);
            std::sort(v.begin(), v.end());
            return v;
        };
        const std::vector<double> a = stamps(), b = stamps();
        ASSERT_EQ(associateByTimestamp(a, b, 0.02), associateAllPairs(a, b, 0.02)) << "trial " << trial;
    }
}

TEST(TumFormat, AListOfThousandsOfEqualStampsIsAssociatedOneToOne) {
    // Pairing every candidate would need 400 M of them; a list like this once ran the fuzzer out of memory.
    const std::vector<double> a(20000, 1.0), b(20000, 1.0);
    const auto pairs = associateByTimestamp(a, b, 0.02);
    ASSERT_EQ(pairs.size(), 20000u);
    for (std::size_t k = 0; k < pairs.size(); ++k)
        ASSERT_EQ(pairs[k], std::make_pair(k, k));
}

class TumSequence : public ::testing::Test {
protected:
    void SetUp() override {
        const fs::path real = fs::absolute(kTum);
        fs::create_directories(dir_.path("rgb"));
        fs::create_directories(dir_.path("depth"));
        for (const char* t : {"1.000", "1.033", "1.066", "1.200"})
            fs::create_symlink(real / "TUM_color.png", dir_.path(std::string("rgb/") + t + ".png"));
        for (const char* t : {"1.005", "1.040", "1.150", "1.199"})
            fs::create_symlink(real / "TUM_depth.png", dir_.path(std::string("depth/") + t + ".png"));
        writeText(dir_.path("rgb.txt"),
                  "# color images\n# file: 'test'\n# timestamp filename\n1.000 rgb/1.000.png\n"
                  "1.033 rgb/1.033.png\n1.066 rgb/1.066.png\n1.200 rgb/1.200.png\n");
        writeText(dir_.path("depth.txt"),
                  "# depth maps\n# timestamp filename\n1.005 depth/1.005.png\n"
                  "1.040 depth/1.040.png\n1.150 depth/1.150.png\n1.199 depth/1.199.png\n");
    }
    TempDir dir_;
};

TEST_F(TumSequence, AssociatesByTimestampAndConvertsDepthWithDefaultIntrinsics) {
    auto source = openReplaySource(dir_.path());
    ASSERT_TRUE(source) << source.error().message;
    ASSERT_EQ((*source)->frameCount(), 3u) << "1.150 has no color image within 0.02 s";
    EXPECT_EQ((*source)->timestampNs(0), 1'005'000'000);
    EXPECT_EQ((*source)->timestampNs(1), 1'040'000'000);
    EXPECT_EQ((*source)->timestampNs(2), 1'199'000'000);
    ASSERT_EQ((*source)->warnings().size(), 1u);
    EXPECT_FALSE((*source)->capabilities().confidence);
    EXPECT_FALSE((*source)->capabilities().pose);
    auto f = loadFrame(**source, 1);
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_EQ(f->sceneDepth->depthMeters.at(320, 240), recording::depthFromUnits(10920, 1.0 / 5000.0));
    EXPECT_FLOAT_EQ(f->sceneDepth->depthMeters.at(100, 400), 8880 / 5000.0f);
    EXPECT_TRUE(f->sceneDepth->confidence.empty());
    EXPECT_EQ(f->capturedImage.width, 640);
    EXPECT_EQ(f->cameraIntrinsics.fx, 525.0);
    EXPECT_EQ(f->cameraIntrinsics.cx, 319.5);
    EXPECT_EQ(f->cameraIntrinsics.cy, 239.5);
    EXPECT_EQ(f->cameraIntrinsics.width, 640);
}

TEST_F(TumSequence, GroundTruthGivesPosesAndACalibrationOverridesTheIntrinsics) {
    writeText(dir_.path("groundtruth.txt"),
              "# timestamp tx ty tz qx qy qz qw\n1.004 1 2 3 0.2 -0.4 0.1 0.9\n1.198 4 5 6 0 0 0 1\n");
    writeText(dir_.path("calib.yaml"), "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 960\n"
                                       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                       "   data: [ 1000., 0., 640., 0., 1000., 480., 0., 0., 1. ]\n");
    auto source = openReplaySource(dir_.path(), {dir_.path("calib.yaml")});
    ASSERT_TRUE(source) << source.error().message;
    EXPECT_TRUE((*source)->capabilities().pose);
    auto first = loadFrame(**source, 0);
    ASSERT_TRUE(first && first->pose);
    EXPECT_EQ(first->pose->cameraToWorld[12], 1.0);
    EXPECT_TRUE(test::isRigid(*first->pose)) << "a quaternion of norm 1.01 becomes a rotation";
    EXPECT_DOUBLE_EQ(first->cameraIntrinsics.fx, 500.0) << "made at 1280x960, applied at 640x480";
    EXPECT_DOUBLE_EQ(first->cameraIntrinsics.cx, 320.0);
    auto middle = loadFrame(**source, 1);
    ASSERT_TRUE(middle);
    EXPECT_FALSE(middle->pose) << "no ground truth within 0.02 s of 1.040";
    auto bad = openReplaySource(dir_.path(), {dir_.path("missing.yaml")});
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("missing.yaml"), std::string::npos);
}

// A Kalibr camchain for a two-sensor camera: cam0 the depth sensor, cam1 the colour sensor at `colourSize`.
std::string kalibrRig(const std::string& colourSize) {
    return "cam0:\n  camera_model: pinhole\n  intrinsics: [525.0, 525.0, 319.5, 239.5]\n"
           "  distortion_model: none\n  resolution: [640, 480]\n"
           "cam1:\n  T_cn_cnm1:\n  - [1, 0, 0, -0.025]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, "
           "1]\n"
           "  camera_model: pinhole\n  intrinsics: [520.0, 521.0, 320.5, 240.5]\n"
           "  distortion_model: radtan\n  distortion_coeffs: [0.1, -0.2, 0.001, 0.002]\n"
           "  resolution: " +
           colourSize + "\n";
}

TEST_F(TumSequence, ATwoSensorCalibrationRidesWithEveryFrameAndMustFitTheStreams) {
    writeText(dir_.path("camchain.yaml"), kalibrRig("[1280, 960]"));
    auto source = openReplaySource(dir_.path(), {dir_.path("camchain.yaml")});
    ASSERT_TRUE(source) << source.error().message;
    EXPECT_NE((*source)->description().find("camchain.yaml (Kalibr camchain)"), std::string::npos);
    auto f = loadFrame(**source, 0);
    ASSERT_TRUE(f) << f.error().message;
    ASSERT_TRUE(f->rig);
    EXPECT_EQ(f->rig->depthToColour.translationMeters[0], -0.025);
    EXPECT_DOUBLE_EQ(f->cameraIntrinsics.fx, 260.0)
        << "the colour sensor's, made at 1280x960, applied at 640x480";
    EXPECT_DOUBLE_EQ(f->depthIntrinsics().fx, 525.0) << "the depth sensor's own";

    writeText(dir_.path("wide.yaml"), kalibrRig("[1280, 720]"));
    auto wide = openReplaySource(dir_.path(), {dir_.path("wide.yaml")});
    ASSERT_TRUE(wide);
    auto refused = loadFrame(**wide, 0);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("cam1.resolution 1280x720"), std::string::npos)
        << refused.error().message;
}

TEST(ReplaySource, UnknownPathsAreClearErrors) {
    TempDir dir;
    auto missing = openReplaySource(dir.path("nothing-here"));
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("does not exist"), std::string::npos);
    auto empty = openReplaySource(dir.path());
    ASSERT_FALSE(empty);
    EXPECT_NE(empty.error().message.find("not a recording, a Stray Scanner directory"), std::string::npos);
    writeText(dir.path("notes.txt"), "hello");
    auto text = openReplaySource(dir.path("notes.txt"));
    ASSERT_FALSE(text);
    EXPECT_NE(text.error().message.find("notes.txt: truncated file"), std::string::npos)
        << text.error().message;
}

// Sizes around the 4-sample blocks the check runs in, with every kind of bad sample in a block and in the
// scalar tail.
TEST(ReplaySource, SanitizeZeroesNanInfiniteAndNegativeDepthAndCountsThem) {
    constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const std::vector<float> samples = {1.5f,  kNan,  -2.0f, kInf,    0.0f, -0.0f,
                                        3.25f, -kInf, 1e30f, -1e-30f, kNan};
    for (std::size_t n = 1; n <= samples.size(); ++n) {
        frame::Plane<float> depth(static_cast<int>(n), 1);
        std::copy_n(samples.begin(), n, depth.pixels.begin());
        std::size_t bad = 0;
        for (std::size_t i = 0; i < n; ++i)
            bad += std::isfinite(samples[i]) && samples[i] >= 0.0f ? 0 : 1;
        EXPECT_EQ(sanitizeDepth(depth), bad) << n << " samples";
        for (std::size_t i = 0; i < n; ++i) {
            const bool good = std::isfinite(samples[i]) && samples[i] >= 0.0f;
            EXPECT_EQ(depth.pixels[i], good ? samples[i] : 0.0f) << "sample " << i << " of " << n;
        }
    }
}

// One answer for every way a capture is opened: by the first bytes where a file has them, else by the
// extension in any case; folders by their entries.
TEST(CaptureKind, ACaptureIsKnownByItsContentOrItsExtensionInAnyCase) {
    const fs::path dir = fs::temp_directory_path() / ("dc-capture-kind-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "stray" / "depth");
    fs::create_directories(dir / "tum");
    fs::create_directories(dir / "empty");
    const auto write = [&](const char* name, const std::string& bytes) {
        std::ofstream(dir / name, std::ios::binary) << bytes;
        return dir / name;
    };
    const std::string recordingMagic(recording::kFileMagic.begin(), recording::kFileMagic.end());
    std::ofstream(dir / "tum" / "rgb.txt") << "# none\n";
    EXPECT_EQ(classifyCapture(write("X.BAG", "not yet a bag")), CaptureKind::RosBag);
    EXPECT_EQ(classifyCapture(write("x.Bag", "not yet a bag")), CaptureKind::RosBag);
    EXPECT_EQ(classifyCapture(write("take-without-a-name", "#ROSBAG V2.0\n")), CaptureKind::RosBag);
    EXPECT_EQ(classifyCapture(write("X.MCAP", "not yet an mcap")), CaptureKind::Mcap);
    EXPECT_EQ(classifyCapture(write("x.Mcap", "not yet an mcap")), CaptureKind::Mcap);
    EXPECT_EQ(classifyCapture(write("unnamed-mcap", std::string("\x89MCAP0\r\n", 8) + "rest")), CaptureKind::Mcap);
    EXPECT_EQ(classifyCapture(write("TAKE.DCREC", "short")), CaptureKind::DcRecording);
    EXPECT_EQ(classifyCapture(write("take.Dcrec", "short")), CaptureKind::DcRecording);
    EXPECT_EQ(classifyCapture(write("renamed.bin", recordingMagic + "rest")), CaptureKind::DcRecording);
    EXPECT_EQ(classifyCapture(write("notes.txt", "a note, longer than eight bytes")), CaptureKind::OtherFile);
    EXPECT_EQ(classifyCapture(dir / "stray"), CaptureKind::StrayCapture);
    EXPECT_EQ(classifyCapture(dir / "tum"), CaptureKind::TumSequence);
    EXPECT_EQ(classifyCapture(dir / "empty"), CaptureKind::Folder);
    EXPECT_EQ(classifyCapture(dir / "missing.dcrec"), CaptureKind::Missing);
    // replay: opens by the same answer: an upper-case recording is read as a recording (its reader names
    // the bad magic), not refused by its name.
    const auto opened = openReplaySource((dir / "TAKE.DCREC").string());
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.error().message.find("TAKE.DCREC"), std::string::npos) << opened.error().message;
    fs::remove_all(dir);
}

} // namespace
} // namespace dc::devices::replay
