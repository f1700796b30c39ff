// ROS bag replay: bags written by Debian's python3-rosbag (make_test_bags.py) in RealSense's layout and a
// camera driver's, replayed through the replay machinery pixel for pixel, and every broken bag the issue
// lists.

#include "devices/recording/frame_codec.h"
#include "devices/replay/replay_device.h"
#include "devices/replay/replay_spec.h"
#include "devices/ros/bag_source.h"
#include "exporting/export.h"
#include "frame/camera_model.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/replay_test_pattern.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace dc::devices::ros {
namespace {

namespace fs = std::filesystem;
using replay::ReplaySource;

using namespace pattern; // the writers' layout and formulas

// The depth sensor's infrared: 8-bit, or the same values spread over 16 bits (the YUYV bag's mono16).
std::uint16_t infraredValue(int x, int y, std::size_t i, bool wide) {
    const int v = (x * 7 + y * 3 + static_cast<int>(i)) & 0xff;
    return static_cast<std::uint16_t>(wide ? v * 257 : v);
}

class BagReplay : public ::testing::Test {
protected:
    // CTest writes the bags once (the RosTestBags fixture); a run of the binary alone writes them itself.
    static void SetUpTestSuite() {
        dir_ = new test::TempDir;
        if (fs::exists(bag("generic.bag")))
            return;
        fs::create_directories(kBagDirectory);
        const std::string command =
            "/usr/bin/python3 tests/ros/make_test_bags.py " + std::string(kBagDirectory);
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    static void TearDownTestSuite() { delete dir_; }
    static std::string bag(const std::string& name) { return std::string(kBagDirectory) + "/" + name; }
    static constexpr const char* kBagDirectory = DC_TEST_BAG_DIRECTORY;
    static std::unique_ptr<ReplaySource> open(const std::string& spec) {
        auto source = replay::openReplaySpecSource(spec);
        EXPECT_TRUE(source) << source.error().message;
        return source ? std::move(*source) : nullptr;
    }
    static void expectDepth(const frame::Frame& f, std::size_t i, double metersPerUnit) {
        ASSERT_TRUE(f.sceneDepth);
        const auto& d = f.sceneDepth->depthMeters;
        ASSERT_EQ(d.width, kDepthW);
        ASSERT_EQ(d.height, kDepthH);
        for (int y = 0; y < kDepthH; ++y)
            for (int x = 0; x < kDepthW; ++x)
                ASSERT_EQ(d.at(x, y), recording::depthFromUnits(depthUnits(x, y, i), metersPerUnit))
                    << "frame " << i << " at " << x << "," << y;
    }
    static void expectRgb(const frame::Frame& f, std::size_t i) {
        ASSERT_EQ(f.capturedImage.format, frame::PixelFormat::Rgb24);
        ASSERT_EQ(f.capturedImage.width, kColorW);
        ASSERT_EQ(f.capturedImage.height, kColorH);
        const auto& bytes = *f.capturedImage.bytes;
        for (int y = 0; y < kColorH; ++y)
            for (int x = 0; x < kColorW; ++x) {
                const auto rgb = colorRgb(x, y, i);
                const std::size_t at = 3 * (static_cast<std::size_t>(y) * kColorW + x);
                ASSERT_EQ(bytes[at], rgb[0]) << "frame " << i << " at " << x << "," << y;
                ASSERT_EQ(bytes[at + 1], rgb[1]);
                ASSERT_EQ(bytes[at + 2], rgb[2]);
            }
    }

    static test::TempDir* dir_;
};
test::TempDir* BagReplay::dir_ = nullptr;

TEST_F(BagReplay, RealSenseBagReplaysEveryFramePixelForPixelInItsDepthUnitsAndStamps) {
    auto source = open(bag("realsense_rgb8.bag"));
    ASSERT_TRUE(source);
    ASSERT_EQ(source->frameCount(), kFrames);
    const Capabilities caps = source->capabilities();
    EXPECT_TRUE(caps.sceneDepth && caps.color);
    EXPECT_FALSE(caps.approximateIntrinsics);
    EXPECT_NE(source->description().find("/device_0/sensor_0/Depth_0/image/data"), std::string::npos);
    EXPECT_NE(source->description().find("/device_0/sensor_1/Color_0/image/data"), std::string::npos);
    // The recorded Depth Units option (0.0001 as a float32), not the 1 mm default.
    const double metersPerUnit = static_cast<double>(0.0001f);
    for (std::size_t i = kFrames; i-- > 0;) { // backwards: every access is a seek
        EXPECT_EQ(source->timestampNs(i), kStartNs + static_cast<std::int64_t>(i) * kFrameNs);
        auto f = replay::loadFrame(*source, i);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(f->timestampNs, source->timestampNs(i));
        expectDepth(*f, i, metersPerUnit);
        expectRgb(*f, i);
        // The depth camera's intrinsics (fx 60, fy 61, cx 31.5, cy 23.5 at 64x48) place the points.
        const frame::Intrinsics k = f->depthIntrinsics();
        EXPECT_DOUBLE_EQ(k.fx, 60.0);
        EXPECT_DOUBLE_EQ(k.fy, 61.0);
        EXPECT_DOUBLE_EQ(k.cx, 31.5);
        EXPECT_DOUBLE_EQ(k.cy, 23.5);
    }
}

TEST_F(BagReplay, RealSenseBagKeepsEachStreamsLensAndTheDepthToColorExtrinsics) {
    auto source = open(bag("realsense_rgb8.bag"));
    ASSERT_TRUE(source);
    const BagRig* rig = bagRig(*source);
    ASSERT_TRUE(rig);
    ASSERT_TRUE(rig->depth && rig->color && rig->depthToColor);
    EXPECT_EQ(rig->depth->distortionModel, "Brown Conrady");
    EXPECT_DOUBLE_EQ(rig->color->intrinsics.fx, 70.0);
    EXPECT_DOUBLE_EQ(rig->color->intrinsics.fy, 71.0);
    EXPECT_DOUBLE_EQ(rig->color->intrinsics.cx, 40.25);
    EXPECT_DOUBLE_EQ(rig->color->intrinsics.cy, 29.75);
    EXPECT_EQ(rig->color->intrinsics.width, kColorW);
    EXPECT_EQ(rig->color->distortionModel, "Inverse Brown Conrady");
    EXPECT_EQ(rig->color->distortion, (std::vector<double>{0.1, -0.2, 0.001, 0.002, 0.03}));
    // The colour stream maps into the depth stream by Rz(0.1) and t = (0.015, 0.001, -0.002): depth ->
    // colour is the inverse, R^T and -R^T t.
    const double c = std::cos(0.1), s = std::sin(0.1);
    const std::array<double, 9> rotation{c, s, 0, -s, c, 0, 0, 0, 1};
    for (int i = 0; i < 9; ++i)
        EXPECT_NEAR(rig->depthToColor->rotation[i], rotation[i], 1e-12) << i;
    EXPECT_NEAR(rig->depthToColor->translationMeters[0], -(c * 0.015 + s * 0.001), 1e-12);
    EXPECT_NEAR(rig->depthToColor->translationMeters[1], -(-s * 0.015 + c * 0.001), 1e-12);
    EXPECT_NEAR(rig->depthToColor->translationMeters[2], 0.002, 1e-12);
}

// What the bag records about its two sensors rides with every frame, so that each point takes its colour
// where the colour sensor sees it; a bag that does not record where the sensors sit keeps one camera's.
TEST_F(BagReplay, RealSenseFramesCarryTheRecordedTwoSensorCalibration) {
    auto source = open(bag("realsense_rgb8.bag"));
    ASSERT_TRUE(source);
    const BagRig* recorded = bagRig(*source);
    ASSERT_TRUE(recorded && recorded->depthToColor);
    auto f = replay::loadFrame(*source, 2);
    ASSERT_TRUE(f) << f.error().message;
    ASSERT_TRUE(f->rig);
    const frame::RigCalibration& rig = *f->rig;
    EXPECT_EQ(rig.depth.intrinsics.fx, 60.0);
    EXPECT_EQ(rig.depth.lens.model, frame::LensModel::None) << "all-zero Brown Conrady bends nothing";
    EXPECT_EQ(rig.colour.intrinsics.fx, 70.0);
    EXPECT_EQ(rig.colour.intrinsics.cy, 29.75);
    EXPECT_EQ(rig.colour.lens.model, frame::LensModel::InverseBrownConrady);
    EXPECT_EQ(rig.colour.lens.coefficients, (std::array<double, 5>{0.1, -0.2, 0.001, 0.002, 0.03}));
    EXPECT_EQ(rig.depthToColour.rotation, recorded->depthToColor->rotation);
    EXPECT_EQ(rig.depthToColour.translationMeters, recorded->depthToColor->translationMeters);
    EXPECT_FALSE(rig.approximate);
    EXPECT_EQ(f->depthIntrinsics().fx, 60.0) << "the depth sensor's own intrinsics place the points";
    EXPECT_EQ(f->cameraIntrinsics.fx, 70.0) << "the image's are the colour sensor's";

    auto generic = open(bag("generic.bag"));
    ASSERT_TRUE(generic);
    auto g = replay::loadFrame(*generic, 0);
    ASSERT_TRUE(g) << g.error().message;
    EXPECT_FALSE(g->rig) << "no transform between the sensors is recorded: one camera's colour";
}

TEST_F(BagReplay, EveryRealSenseColourEncodingDecodesToTheRecordedImage) {
    for (const char* encoding : {"bgr8", "rgba8"}) {
        auto source = open(bag(std::string("realsense_") + encoding + ".bag"));
        ASSERT_TRUE(source);
        auto f = replay::loadFrame(*source, 3);
        ASSERT_TRUE(f) << f.error().message;
        SCOPED_TRACE(encoding);
        expectRgb(*f, 3);
    }
    // YUYV (in an LZ4-compressed bag, as the Viewer writes) stays packed 4:2:2; the writer's pattern puts
    // (r, g) of each pixel in its two bytes.
    auto source = open(bag("realsense_YUYV.bag"));
    ASSERT_TRUE(source);
    auto f = replay::loadFrame(*source, 2);
    ASSERT_TRUE(f) << f.error().message;
    ASSERT_EQ(f->capturedImage.format, frame::PixelFormat::Yuyv);
    ASSERT_EQ(f->capturedImage.bytes->size(), static_cast<std::size_t>(kColorW * kColorH * 2));
    for (int y = 0; y < kColorH; ++y)
        for (int x = 0; x < kColorW; ++x) {
            const std::size_t at = 2 * (static_cast<std::size_t>(y) * kColorW + x);
            ASSERT_EQ((*f->capturedImage.bytes)[at], colorRgb(x, y, 2)[0]);
            ASSERT_EQ((*f->capturedImage.bytes)[at + 1], colorRgb(x, y, 2)[1]);
        }
}

TEST_F(BagReplay, RealSenseFramesCarryTheInfraredStreamPixelForPixelIn8And16Bits) {
    for (const char* encoding : {"rgb8", "YUYV"}) {
        const bool wide = std::string(encoding) == "YUYV";
        auto source = open(bag(std::string("realsense_") + encoding + ".bag"));
        ASSERT_TRUE(source);
        EXPECT_NE(source->description().find("infrared /device_0/sensor_0/Infrared_1/image/data"),
                  std::string::npos);
        for (std::size_t i = 0; i < kFrames; ++i) {
            auto f = replay::loadFrame(*source, i);
            ASSERT_TRUE(f) << f.error().message;
            ASSERT_TRUE(f->infrared) << encoding << " frame " << i;
            ASSERT_EQ(f->infrared->width, kDepthW);
            ASSERT_EQ(f->infrared->height, kDepthH);
            for (int y = 0; y < kDepthH; ++y)
                for (int x = 0; x < kDepthW; ++x)
                    ASSERT_EQ(f->infrared->at(x, y), infraredValue(x, y, i, wide))
                        << encoding << " frame " << i << " at " << x << "," << y;
        }
    }
}

TEST_F(BagReplay, BagWithoutAnInfraredStreamGivesFramesWithoutOne) {
    // generic.bag's /camera/ir/image_raw is Bayer, not an infrared intensity image.
    auto source = open(bag("generic.bag"));
    ASSERT_TRUE(source);
    EXPECT_EQ(source->description().find("infrared"), std::string::npos);
    auto f = replay::loadFrame(*source, 2);
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_FALSE(f->infrared);
}

TEST_F(BagReplay, GenericBagFindsDepthAndColourByEncodingWithCameraInfoBeside) {
    auto source = open(bag("generic.bag"));
    ASSERT_TRUE(source);
    EXPECT_NE(source->description().find("/camera/depth/image_rect_raw"), std::string::npos);
    EXPECT_NE(source->description().find("/camera/color/image_raw"), std::string::npos);
    auto f = replay::loadFrame(*source, 4);
    ASSERT_TRUE(f) << f.error().message;
    // 32FC1 is meters: the writer stored float(units * 0.001).
    const auto& d = f->sceneDepth->depthMeters;
    for (int y = 0; y < kDepthH; ++y)
        for (int x = 0; x < kDepthW; ++x)
            ASSERT_EQ(d.at(x, y), static_cast<float>(depthUnits(x, y, 4) * 0.001));
    expectRgb(*f, 4); // recorded as bgr8
    const frame::Intrinsics k = f->depthIntrinsics();
    EXPECT_DOUBLE_EQ(k.fx, 50.0);
    EXPECT_DOUBLE_EQ(k.fy, 52.0);
    EXPECT_DOUBLE_EQ(k.cx, 32.0);
    EXPECT_DOUBLE_EQ(k.cy, 24.0);
}

// image_transport's compressedDepth (PNG16 behind its header) and compressed (PNG) topics, as a ROS 1
// robot records them to save bandwidth: the same pixels as the raw topics, camera_info found beside the
// raw topic's name.
TEST_F(BagReplay, CompressedTopicsReplayPixelForPixelWithTheirRawTopicsCalibration) {
    auto source = open(bag("compressed.bag"));
    ASSERT_TRUE(source);
    ASSERT_EQ(source->frameCount(), kFrames);
    EXPECT_TRUE(source->capabilities().color);
    EXPECT_NE(source->description().find("/camera/depth/image_rect_raw/compressedDepth"), std::string::npos);
    EXPECT_NE(source->description().find("/camera/color/image_raw/compressed"), std::string::npos);
    for (std::size_t i = kFrames; i-- > 0;) {
        EXPECT_EQ(source->timestampNs(i), kStartNs + static_cast<std::int64_t>(i) * kFrameNs);
        auto f = replay::loadFrame(*source, i);
        ASSERT_TRUE(f) << f.error().message;
        expectDepth(*f, i, 0.001);
        expectRgb(*f, i);
        EXPECT_DOUBLE_EQ(f->depthIntrinsics().fx, 50.0);
        EXPECT_DOUBLE_EQ(f->depthIntrinsics().cy, 24.0);
    }
}

TEST_F(BagReplay, TopicsOptionPicksTheDepthTopicAndRefusesWhatIsNotOne) {
    auto source = open("replay:" + bag("generic.bag") + ":topics=/camera/aligned/image_raw");
    ASSERT_TRUE(source);
    EXPECT_FALSE(source->capabilities().color);
    auto f = replay::loadFrame(*source, 1);
    ASSERT_TRUE(f) << f.error().message;
    expectDepth(*f, 1, 0.001); // 16UC1 in millimetres
    EXPECT_TRUE(f->capturedImage.empty());

    auto fails = [&](const std::string& topics, const std::string& needle) {
        auto s = replay::openReplaySpecSource("replay:" + bag("generic.bag") + ":topics=" + topics);
        ASSERT_FALSE(s) << topics;
        EXPECT_NE(s.error().message.find(needle), std::string::npos) << s.error().message;
    };
    fails("/status", "is std_msgs/String, not sensor_msgs/Image");
    fails("/camera/ir/image_raw", "'bayer_rggb8'");
    fails("/camera/depth/image_rect_raw,/camera/aligned/image_raw", "not a colour image");
    fails("/nowhere", "has no topic /nowhere");
}

// A bag is known by its content: named by another system (X.BAG) or with no extension at all, it replays.
TEST_F(BagReplay, ABagOpensWhateverItsNameSays) {
    for (const char* name : {"TAKE.BAG", "take-without-extension"}) {
        const std::string renamed = dir_->path(name);
        fs::copy_file(bag("realsense_rgb8.bag"), renamed, fs::copy_options::overwrite_existing);
        auto s = replay::openReplaySource(renamed);
        ASSERT_TRUE(s) << name << ": " << s.error().message;
        EXPECT_EQ((*s)->frameCount(), kFrames) << name;
    }
}

TEST_F(BagReplay, BrokenBagsGiveOneClearErrorAndNeverACrash) {
    auto fails = [&](const std::string& path, const std::string& needle) {
        auto s = replay::openReplaySource(path);
        ASSERT_FALSE(s) << path;
        EXPECT_NE(s.error().message.find(needle), std::string::npos) << s.error().message;
        EXPECT_EQ(s.error().message.find('\n'), std::string::npos);
    };
    fails(bag("no_images.bag"), "has no depth image topic");
    std::ofstream(dir_->path("text.bag")) << "not a bag at all\n";
    fails(dir_->path("text.bag"), "is not a readable ROS bag");
    std::ofstream{dir_->path("empty.bag")};
    fails(dir_->path("empty.bag"), "is not a readable ROS bag");
    // Cut anywhere: the open fails cleanly, or the frames it lists either decode or fail with an error.
    const auto whole = fs::file_size(bag("realsense_rgb8.bag"));
    for (const double fraction : {0.1, 0.5, 0.9, 0.999}) {
        const std::string cut = dir_->path("cut.bag");
        fs::copy_file(bag("realsense_rgb8.bag"), cut, fs::copy_options::overwrite_existing);
        fs::resize_file(cut, static_cast<std::uintmax_t>(static_cast<double>(whole) * fraction));
        auto s = replay::openReplaySource(cut);
        if (!s) {
            EXPECT_NE(s.error().message.find(cut), std::string::npos) << s.error().message;
            continue;
        }
        for (std::size_t i = 0; i < (*s)->frameCount(); ++i)
            if (auto f = replay::loadFrame(**s, i); f)
                expectDepth(*f, i, static_cast<double>(0.0001f));
    }
}

TEST_F(BagReplay, StampsThatJumpBackKeepReplayTimeNonDecreasingWithAWarning) {
    auto source = open(bag("clock_jumps_back.bag"));
    ASSERT_TRUE(source);
    ASSERT_EQ(source->frameCount(), kFrames);
    // Recorded stamps 0, 1, 3, 2, 4 frames: the fourth keeps the third's.
    const std::int64_t expected[] = {0, 1, 3, 3, 4};
    for (std::size_t i = 0; i < kFrames; ++i)
        EXPECT_EQ(source->timestampNs(i), kStartNs + expected[i] * kFrameNs) << i;
    const auto warnings = source->warnings();
    EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                            [](const std::string& w) { return w.find("1 images") != std::string::npos; }),
              1);
}

TEST_F(BagReplay, ReplayDeviceSeeksExactlyInABag) {
    auto source = open(bag("realsense_rgb8.bag"));
    ASSERT_TRUE(source);
    replay::ReplayDevice device(std::move(source), {.startPlaying = false});
    ASSERT_TRUE(device.open());
    ASSERT_TRUE(device.start());
    auto control = device.control();
    for (const std::size_t target : {4u, 0u, 2u, 3u, 1u}) {
        const std::uint64_t generation = control->seekToIndex(target);
        frame::FramePtr f;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (!f && std::chrono::steady_clock::now() < deadline) {
            auto r = device.capture(std::chrono::milliseconds(50));
            if (r.kind == CaptureResult::Kind::Frame && r.frame->replay->seekGeneration >= generation)
                f = r.frame;
        }
        ASSERT_TRUE(f) << target;
        EXPECT_EQ(f->replay->index, target);
        EXPECT_EQ(f->timestampNs, kStartNs + static_cast<std::int64_t>(target) * kFrameNs);
        expectDepth(*f, target, static_cast<double>(0.0001f));
    }
}

TEST_F(BagReplay, Png16ExportOfAMillimetreBagEqualsTheRecordedDepth) {
    auto source = open("replay:" + bag("generic.bag") + ":topics=/camera/aligned/image_raw");
    ASSERT_TRUE(source);
    const std::string out = dir_->path("export");
    exporting::ExportOptions options;
    options.format = exporting::ExportFormat::Png16;
    options.outDirectory = out;
    auto result = exporting::exportFrames(*source, options);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_EQ(result->framesWritten, kFrames);
    for (std::size_t i = 0; i < kFrames; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "/depth/%06zu.png", i);
        const cv::Mat png = cv::imread(out + name, cv::IMREAD_ANYDEPTH);
        ASSERT_EQ(png.type(), CV_16UC1) << name;
        for (int y = 0; y < kDepthH; ++y)
            for (int x = 0; x < kDepthW; ++x)
                ASSERT_EQ(png.at<std::uint16_t>(y, x), depthUnits(x, y, i)) << name << " " << x << "," << y;
    }
}

TEST(RosImage, MessagesThatClaimMoreThanTheyHoldOrUnknownEncodingsAreRefused) {
    RosImage image{0, "camera", "16UC1", 4, 2, 8, false, std::vector<std::uint8_t>(15)};
    auto short16 = depthFromImage(image, 0.001);
    ASSERT_FALSE(short16);
    EXPECT_NE(short16.error().message.find("too few"), std::string::npos) << short16.error().message;
    image.data.resize(16);
    image.step = 7; // less than a row
    EXPECT_FALSE(depthFromImage(image, 0.001));
    image.step = 8;
    ASSERT_TRUE(depthFromImage(image, 0.001));
    image.width = 0;
    EXPECT_FALSE(depthFromImage(image, 0.001));

    RosImage yuyv{0, "camera", "YUYV", 3, 1, 6, false, std::vector<std::uint8_t>(6)};
    auto odd = colorFromImage(yuyv);
    ASSERT_FALSE(odd);
    EXPECT_NE(odd.error().message.find("odd width"), std::string::npos);
    RosImage bayer{0, "camera", "bayer_rggb8", 2, 2, 2, false, std::vector<std::uint8_t>(4)};
    EXPECT_FALSE(colorFromImage(bayer));
    EXPECT_FALSE(depthFromImage(bayer, 0.001));
    EXPECT_EQ(imageKind("bayer_rggb8"), ImageKind::Other);
}

TEST(RosImage, BigEndianDepthAndUyvyColourAreReadAsTheyAreStored) {
    // 0x0102 units big-endian, 1 mm each.
    RosImage depth{0, "camera", "16UC1", 1, 1, 2, true, {0x01, 0x02}};
    auto d = depthFromImage(depth, 0.001);
    ASSERT_TRUE(d) << d.error().message;
    EXPECT_EQ(d->at(0, 0), recording::depthFromUnits(0x0102, 0.001));
    // ROS's yuv422 is UYVY: U Y0 V Y1 becomes Y0 U Y1 V.
    RosImage uyvy{0, "camera", "yuv422", 2, 1, 4, false, {10, 20, 30, 40}};
    auto c = colorFromImage(uyvy);
    ASSERT_TRUE(c) << c.error().message;
    ASSERT_EQ(c->format, frame::PixelFormat::Yuyv);
    EXPECT_EQ(*c->bytes, (std::vector<std::uint8_t>{20, 10, 40, 30}));
}

} // namespace
} // namespace dc::devices::ros
