#include "devices/frame_pairer.h"
#include "devices/uvc/live_source_spec.h"
#include "devices/uvc/usb/known_cameras.h"
#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/v4l2/node_probe.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "frame/calibration.h"
#include "frame/color.h"
#include "frame/jpeg_codec.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>

namespace dc::devices {
namespace {

namespace fs = std::filesystem;

// ---- Z16 -> meters and camera images ------------------------------------------------------------

TEST(PixelFormats, Z16BecomesMetersOnceWithRowPaddingSkipped) {
    // 3x2 pixels, rows padded to 8 bytes (drivers may do that); the padding holds garbage.
    const std::vector<std::uint8_t> raw{0x00, 0x00, 0xe8, 0x03, 0xff, 0xff, 0xaa, 0xbb,  // 0, 1000, 65535
                                        0x01, 0x00, 0x10, 0x27, 0x34, 0x12, 0xcc, 0xdd}; // 1, 10000, 0x1234
    frame::Plane<float> meters;
    v4l2::depthToMeters(raw, 3, 2, 8, 0.001f, meters);
    ASSERT_EQ(meters.width, 3);
    const std::vector<float> expected{0.0f,       1000 * 0.001f,  65535 * 0.001f,
                                      1 * 0.001f, 10000 * 0.001f, 0x1234 * 0.001f};
    EXPECT_EQ(meters.pixels, expected) << "raw 0 (no measurement) stays 0, the rest is raw * scale";
    v4l2::depthToMeters(raw, 3, 2, 8, 0.00025f, meters);
    EXPECT_FLOAT_EQ(meters.at(1, 0), 0.25f);
}

TEST(PixelFormats, CameraImagesAreCopiedWithoutPaddingAndShortOnesRefused) {
    std::vector<std::uint8_t> yuyv(2 * 8); // 2x2 YUYV, 8-byte rows (4 bytes padding)
    for (std::size_t i = 0; i < yuyv.size(); ++i)
        yuyv[i] = static_cast<std::uint8_t>(i);
    auto image = v4l2::toCapturedImage(V4L2_PIX_FMT_YUYV, yuyv, 2, 2, 8);
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(*image->bytes, (std::vector<std::uint8_t>{0, 1, 2, 3, 8, 9, 10, 11}));
    EXPECT_FALSE(v4l2::toCapturedImage(V4L2_PIX_FMT_YUYV, std::span(yuyv).first(9), 2, 2, 8));
    const std::vector<std::uint8_t> grey{10, 20, 30, 40};
    auto g = v4l2::toCapturedImage(V4L2_PIX_FMT_GREY, grey, 2, 2, 2);
    ASSERT_TRUE(g);
    EXPECT_EQ(g->format, frame::PixelFormat::Nv12);
    EXPECT_EQ(*g->bytes, (std::vector<std::uint8_t>{10, 20, 30, 40, 128, 128})) << "grey with neutral chroma";
    EXPECT_FALSE(v4l2::toCapturedImage(V4L2_PIX_FMT_NV12, std::vector<std::uint8_t>(100), 3, 2, 3))
        << "odd-width NV12 cannot be stored";
}

TEST(PixelFormats, MjpegStaysCompressedAndGarbageOrAWrongSizeIsAnError) {
    cv::Mat bgr(4, 6, CV_8UC3, cv::Scalar(0, 0, 255)); // red
    std::vector<std::uint8_t> jpeg;
    ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg));
    auto image = v4l2::toCapturedImage(V4L2_PIX_FMT_MJPEG, jpeg, 6, 4, 0);
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->format, frame::PixelFormat::Jpeg);
    EXPECT_EQ(*image->bytes, jpeg) << "the capture thread keeps the camera's bytes; decoding comes later";
    const auto decoded = frame::JpegDecoder().decode(*image);
    ASSERT_TRUE(decoded) << decoded.error().message;
    EXPECT_GT(frame::pixelRgb(*decoded, 0, 0).r, 0.8f) << "and the decoded image is the red one";
    const std::vector<std::uint8_t> garbage(50, 0x42);
    EXPECT_FALSE(v4l2::toCapturedImage(V4L2_PIX_FMT_MJPEG, garbage, 6, 4, 0));
    EXPECT_FALSE(v4l2::toCapturedImage(V4L2_PIX_FMT_MJPEG, jpeg, 8, 8, 0)) << "wrong size";
}

TEST(PixelFormats, FourccsRoundTripAndRolesFollowTheFormat) {
    EXPECT_EQ(v4l2::fourccToString(V4L2_PIX_FMT_Z16), "Z16 ");
    EXPECT_EQ(v4l2::parseFourcc("z16"), V4L2_PIX_FMT_Z16);
    EXPECT_EQ(v4l2::parseFourcc("Y16"), V4L2_PIX_FMT_Y16);
    EXPECT_FALSE(v4l2::parseFourcc("TOOLONG"));
    EXPECT_EQ(v4l2::roleOf(V4L2_PIX_FMT_Y16), v4l2::FormatRole::Depth);
    EXPECT_EQ(v4l2::roleOf(V4L2_PIX_FMT_MJPEG), v4l2::FormatRole::Color);
    EXPECT_EQ(v4l2::roleOf(V4L2_PIX_FMT_GREY), v4l2::FormatRole::Guide);
}

// ---- modes and node roles ------------------------------------------------------------------------

TEST(ChooseMode, DefaultsToTheLargestSizeUpTo720pAnd30Fps) {
    const std::vector<v4l2::V4l2Mode> modes{{V4L2_PIX_FMT_Z16, 1280, 720, {90, 30, 15}},
                                            {V4L2_PIX_FMT_Z16, 640, 480, {60, 30}},
                                            {V4L2_PIX_FMT_Z16, 1920, 1080, {30}},
                                            {V4L2_PIX_FMT_YUYV, 320, 240, {30}}};
    auto m = v4l2::chooseMode(modes, {V4L2_PIX_FMT_Z16, 0, 0, 0});
    ASSERT_TRUE(m);
    EXPECT_EQ(m->width, 1280);
    EXPECT_DOUBLE_EQ(m->fps, 30);
    m = v4l2::chooseMode(modes, {V4L2_PIX_FMT_Z16, 640, 480, 50});
    ASSERT_TRUE(m);
    EXPECT_DOUBLE_EQ(m->fps, 60) << "the nearest offered rate";
    auto missing = v4l2::chooseMode(modes, {V4L2_PIX_FMT_Z16, 800, 600, 0});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("640x480"), std::string::npos)
        << "the error lists what is offered";
    EXPECT_FALSE(v4l2::chooseMode(modes, {V4L2_PIX_FMT_Y16, 0, 0, 0}));
}

TEST(NodeRoles, Z16BeatsY16AndColorAndInfraredAreFound) {
    auto node = [](std::string path, std::vector<std::uint32_t> fourccs) {
        v4l2::ProbedNode n{std::move(path), {}, {}};
        for (std::uint32_t f : fourccs)
            n.modes.push_back({f, 640, 480, {30}});
        return n;
    };
    // RealSense-like: an infrared node with GREY and Y16 (calibration) comes before the Z16 node.
    const std::vector<v4l2::ProbedNode> nodes{node("/dev/video0", {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_Y16}),
                                              node("/dev/video2", {V4L2_PIX_FMT_Z16}),
                                              node("/dev/video4", {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG})};
    const v4l2::NodeRoles roles = v4l2::assignRoles(nodes);
    EXPECT_EQ(roles.depth, "/dev/video2");
    EXPECT_EQ(roles.color, "/dev/video4");
    EXPECT_EQ(roles.infrared, "/dev/video0");
    EXPECT_EQ(v4l2::assignRoles({node("/dev/video9", {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_Y16})}).depth,
              "/dev/video9")
        << "Y16 alone is taken as depth";
}

// ---- depth/color pairing ---------------------------------------------------------------------------

StampedDepth depthAt(std::uint64_t seq, std::int64_t ms) {
    return {seq, ms * 1'000'000, frame::Plane<float>(1, 1, static_cast<float>(seq))};
}
StampedImage colorAt(std::uint64_t seq, std::int64_t ms) {
    return {seq, ms * 1'000'000, {}};
}

TEST(FramePairer, PairsTheNearestColorWithinHalfAFrame) {
    FramePairer p(16'000'000);
    p.pushDepth(depthAt(0, 100));
    EXPECT_FALSE(p.pop()) << "its color may still come";
    p.pushColor(colorAt(0, 104));
    auto pair = p.pop();
    ASSERT_TRUE(pair);
    ASSERT_TRUE(pair->color);
    EXPECT_EQ(pair->color->timestampNs, 104'000'000);
    // Color first, then depth a little later.
    p.pushColor(colorAt(1, 131));
    p.pushDepth(depthAt(1, 133));
    pair = p.pop();
    ASSERT_TRUE(pair && pair->color);
    EXPECT_EQ(pair->color->sequence, 1u);
    EXPECT_EQ(p.paired(), 2u);
}

TEST(FramePairer, ReleasesDepthAloneWhenItsColorCannotCome) {
    FramePairer p(16'000'000);
    p.pushDepth(depthAt(0, 100));
    p.pushColor(colorAt(0, 150)); // the color stream skipped this moment
    auto pair = p.pop();
    ASSERT_TRUE(pair);
    EXPECT_FALSE(pair->color);
    // A stalled color node: depth is not held back for more than kMaxPendingDepth frames.
    FramePairer q(16'000'000);
    for (int i = 0; i <= static_cast<int>(FramePairer::kMaxPendingDepth); ++i)
        q.pushDepth(depthAt(static_cast<std::uint64_t>(i), 100 + 33 * i));
    pair = q.pop();
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->depth.sequence, 0u) << "in order";
    EXPECT_EQ(q.unpaired(), 1u);
}

TEST(FramePairer, FramesWithoutTimestampsPairBySequence) {
    FramePairer p(16'000'000);
    p.pushColor({5, 0, {}});
    p.pushColor({6, 0, {}});
    p.pushDepth({6, 0, frame::Plane<float>(1, 1)});
    auto pair = p.pop();
    ASSERT_TRUE(pair && pair->color);
    EXPECT_EQ(pair->color->sequence, 6u);
}

// ---- calibration files ---------------------------------------------------------------------------

TEST(Calibration, ReadsOpenCvYaml) {
    const auto c = frame::parseCalibration(R"(%YAML:1.0
---
image_width: 1280
image_height: 720
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 640., 0., 639.5, 0., 641., 359.5, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0., 0., 0., 0., 0. ]
)",
                                           "cv.yaml");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->format, "OpenCV YAML");
    EXPECT_DOUBLE_EQ(c->intrinsics.fx, 640.0);
    EXPECT_DOUBLE_EQ(c->intrinsics.fy, 641.0);
    EXPECT_DOUBLE_EQ(c->intrinsics.cy, 359.5);
    EXPECT_EQ(c->intrinsics.width, 1280);
}

TEST(Calibration, ReadsRosCameraInfoYaml) {
    const auto c = frame::parseCalibration(R"(image_width: 640
image_height: 480
camera_name: depth_camera
camera_matrix:
  rows: 3
  cols: 3
  data: [385.5, 0, 320.25, 0, 385.5, 241.75, 0, 0, 1]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [0, 0, 0, 0, 0]
)",
                                           "ros.yaml");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->format, "ROS camera_info YAML");
    EXPECT_DOUBLE_EQ(c->intrinsics.cx, 320.25);
    EXPECT_EQ(c->intrinsics.height, 480);
    const frame::Intrinsics half = c->intrinsics.scaledTo(320, 240);
    EXPECT_DOUBLE_EQ(half.fx, 385.5 / 2);
}

TEST(Calibration, BadFilesAreErrorsThatNameTheFile) {
    for (const char* text : {"image_width: [unclosed", "image_width: 640\nimage_height: 480\n",
                             "image_width: 640\nimage_height: 480\ncamera_matrix:\n  data: [1, 2, 3]\n",
                             "camera_matrix:\n  data: [385.5, 0, 320, 0, 385.5, 240, 0, 0, 1]\n"}) {
        const auto c = frame::parseCalibration(text, "bad.yaml");
        ASSERT_FALSE(c) << text;
        EXPECT_NE(c.error().message.find("bad.yaml"), std::string::npos) << c.error().message;
    }
    EXPECT_FALSE(frame::loadCalibration("/nonexistent/calib.yaml"));
}

TEST(Calibration, TheFieldOfViewDefaultIsAPinholeWithThatAngle) {
    const frame::Intrinsics k = frame::intrinsicsFromFieldOfView(640, 480, 90.0);
    EXPECT_NEAR(k.fx, 320.0, 1e-9) << "tan(45 deg) = 1";
    EXPECT_DOUBLE_EQ(k.fy, k.fx);
    EXPECT_DOUBLE_EQ(k.cx, 320.0);
}

// ---- sysfs: USB device -> V4L2 nodes ---------------------------------------------------------------

class FakeSysfs : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() / ("dc-sysfs-" + std::to_string(::getpid()));
        fs::remove_all(root_);
        const fs::path dev = root_ / "devices/platform/dummy_hcd.0/usb1/1-1";
        attribute(dev / "idVendor", "8086");
        attribute(dev / "idProduct", "0b07");
        attribute(dev / "manufacturer", "Fake Depth Inc");
        attribute(dev / "product", "Virtual Z16 Depth Camera");
        attribute(dev / "serial", "VDC0001");
        attribute(dev / "devnum", "2");
        attribute(dev / "1-1:1.0/bInterfaceClass", "0e");
        attribute(dev / "1-1:1.1/bInterfaceClass", "0e");
        attribute(root_ / "devices/platform/dummy_hcd.0/usb1/idVendor", "1d6b"); // the root hub
        fs::create_directories(root_ / "bus/usb/devices");
        fs::create_directories(root_ / "class/video4linux");
        fs::create_directory_symlink("../../../devices/platform/dummy_hcd.0/usb1/1-1",
                                     root_ / "bus/usb/devices/1-1");
        fs::create_directory_symlink("../../../devices/platform/dummy_hcd.0/usb1/1-1/1-1:1.0",
                                     root_ / "bus/usb/devices/1-1:1.0");
        fs::create_directory_symlink("../../../devices/platform/dummy_hcd.0/usb1",
                                     root_ / "bus/usb/devices/usb1");
        for (const char* node : {"video2", "video10"}) // numeric order is not name order
            videoNode(dev / "1-1:1.0/video4linux" / node,
                      "../../devices/platform/dummy_hcd.0/usb1/1-1/1-1:1.0/video4linux/" + std::string(node));
        // A v4l2loopback-like virtual node and the gadget side of a USB gadget.
        videoNode(root_ / "devices/virtual/video4linux/video20", "../../devices/virtual/video4linux/video20",
                  false);
        attribute(root_ / "devices/platform/dummy_udc.0/gadget.0/x", "");
        fs::create_directories(root_ / "bus/gadget");
        videoNode(root_ / "devices/platform/dummy_udc.0/gadget.0/video4linux/video0",
                  "../../devices/platform/dummy_udc.0/gadget.0/video4linux/video0");
        fs::create_directory_symlink("../../../../bus/gadget",
                                     root_ / "devices/platform/dummy_udc.0/gadget.0/subsystem");
    }
    void TearDown() override { fs::remove_all(root_); }

    static void attribute(const fs::path& path, const std::string& value) {
        fs::create_directories(path.parent_path());
        std::ofstream(path) << value << "\n";
    }
    // The node's directory, its /sys/class/video4linux link and (for real devices) its "device" link.
    void videoNode(const fs::path& dir, const std::string& classLink, bool withDevice = true) {
        fs::create_directories(dir);
        fs::create_directory_symlink(classLink, root_ / "class/video4linux" / dir.filename());
        if (withDevice)
            fs::create_directory_symlink("../..", dir / "device");
    }

    fs::path root_;
};

TEST_F(FakeSysfs, MapsAUsbDeviceToItsVideoNodesAndBack) {
    const usb::Sysfs sysfs(root_.string());
    EXPECT_EQ(sysfs.videoNodesOf("1-1"), (std::vector<std::string>{"/dev/video2", "/dev/video10"}));
    EXPECT_TRUE(sysfs.videoNodesOf("1-2").empty());
    const auto owner = sysfs.usbDeviceOf("/dev/video10");
    ASSERT_TRUE(owner);
    EXPECT_EQ(owner->id(), "8086:0b07");
    EXPECT_EQ(owner->product, "Virtual Z16 Depth Camera");
    EXPECT_EQ(owner->serial, "VDC0001");
    EXPECT_EQ(owner->sysfsName(), "1-1");
    EXPECT_EQ(owner->address, 2);
    EXPECT_TRUE(owner->hasVideoInterface);
    EXPECT_FALSE(sysfs.usbDeviceOf("/dev/video20")) << "a virtual driver's node has no USB device";
    EXPECT_FALSE(sysfs.usbDeviceOf("/dev/video99"));
    EXPECT_EQ(sysfs.allVideoNodes(),
              (std::vector<std::string>{"/dev/video0", "/dev/video2", "/dev/video10", "/dev/video20"}));
    EXPECT_EQ(sysfs.busOf("/dev/video0"), "gadget");
    const auto devices = sysfs.usbDevices();
    ASSERT_EQ(devices.size(), 1u) << "root hubs and interfaces are not devices";
    EXPECT_EQ(devices[0].ports, std::vector<int>{1});
}

// ---- --source grammar ----------------------------------------------------------------------------

TEST(LiveSourceSpec, ParsesNodesUsbIdsSerialsAndOptions) {
    auto c =
        parseLiveSourceSpec("v4l2:/dev/video3:640x480@15:scale=0.0001:color=none:watchdog=500:format=y16");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->depthNode, "/dev/video3");
    EXPECT_EQ(c->width, 640);
    EXPECT_DOUBLE_EQ(c->fps, 15);
    EXPECT_FLOAT_EQ(*c->depthScaleMeters, 0.0001f);
    EXPECT_FALSE(c->color);
    EXPECT_EQ(c->watchdog.count(), 500);
    EXPECT_EQ(*c->depthFourcc, V4L2_PIX_FMT_Y16);
    c = parseLiveSourceSpec("usb:8086:0B07:VDC0001:color=/dev/video4");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->usb->vendorId, 0x8086);
    EXPECT_EQ(c->usb->productId, 0x0b07);
    EXPECT_EQ(c->usb->serial, "VDC0001");
    EXPECT_EQ(c->colorNode, "/dev/video4");
    c = parseLiveSourceSpec("usb:8086:0b07:1280x720");
    ASSERT_TRUE(c);
    EXPECT_TRUE(c->usb->serial.empty()) << "a mode is not a serial";
    for (const char* bad :
         {"usb:8086", "usb:xyz:0b07", "v4l2:", "v4l2:/dev/video0:scale=-1", "v4l2:/dev/video0:bogus",
          "v4l2:/dev/video0:format=YUYV", "v4l2:/dev/video0:calib=/nonexistent.yaml", "v4l2:/dev/video0:0x0"})
        EXPECT_FALSE(parseLiveSourceSpec(bad)) << bad;
}

// A depth and colour camera's calibration in Kalibr's layout: depth 640x480 (cam0), colour 320x240
// (cam1) 25 mm to the side.
constexpr const char* kRigCamchain = R"(cam0:
  camera_model: pinhole
  distortion_model: none
  distortion_coeffs: []
  intrinsics: [500.0, 500.0, 319.5, 239.5]
  resolution: [640, 480]
cam1:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, -0.025]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_model: none
  distortion_coeffs: []
  intrinsics: [300.0, 300.0, 159.5, 119.5]
  resolution: [320, 240]
)";

std::string writeTemp(const std::string& name, const std::string& text) {
    const fs::path path = fs::temp_directory_path() / (std::to_string(::getpid()) + "-" + name);
    std::ofstream(path) << text;
    return path.string();
}

// The window's mode list reopens the camera with its spec rewritten: the new mode and format replace the old
// ones wherever they stood, every other option stays, and a spec that is no live camera is refused.
TEST(LiveSourceSpec, ADepthModeChosenReplacesTheSpecsModeAndFormatOnly) {
    const StreamMode mode{"Y16", 848, 480, 15};
    EXPECT_EQ(*withDepthMode("v4l2:/dev/video3", mode), "v4l2:/dev/video3:848x480@15:format=Y16");
    EXPECT_EQ(*withDepthMode("v4l2:/dev/video3:640x480@30:scale=0.0001:format=Z16:color=none", mode),
              "v4l2:/dev/video3:848x480@15:format=Y16:scale=0.0001:color=none");
    EXPECT_EQ(*withDepthMode("usb:8086:0b07:VDC0001:1280x720:watchdog=500", {"Z16", 640, 360, 29.97}),
              "usb:8086:0b07:VDC0001:640x360@29.97:format=Z16:watchdog=500");
    EXPECT_EQ(*withDepthMode("usb:8086:0b07", mode), "usb:8086:0b07:848x480@15:format=Y16");
    const auto parsed = parseLiveSourceSpec(*withDepthMode("usb:8086:0b07:VDC0001:color=none", mode));
    ASSERT_TRUE(parsed) << parsed.error().message;
    EXPECT_EQ(parsed->width, 848);
    EXPECT_EQ(parsed->fps, 15.0);
    EXPECT_FALSE(withDepthMode("v4l2:", mode).ok());
}

// The colour node's mode goes in colormode= and colorformat=, which replace the old ones wherever they
// stood; the depth mode and every other option stay, and the spec parses back to the mode chosen.
TEST(LiveSourceSpec, AColourModeChosenReplacesTheSpecsColourModeAndFormatOnly) {
    const StreamMode mode{"MJPG", 1280, 720, 15};
    EXPECT_EQ(*withColorMode("v4l2:/dev/video3:color=/dev/video5", mode),
              "v4l2:/dev/video3:colormode=1280x720@15:colorformat=MJPG:color=/dev/video5");
    EXPECT_EQ(
        *withColorMode("usb:8086:0b07:VDC0001:848x480@30:colorformat=YUYV:scale=0.0001:"
                       "colormode=640x480@30:watchdog=500",
                       {"NV12", 424, 240, 6}),
        "usb:8086:0b07:VDC0001:colormode=424x240@6:colorformat=NV12:848x480@30:scale=0.0001:watchdog=500");
    const auto parsed = parseLiveSourceSpec(*withColorMode("usb:8086:0b07:848x480@30:format=Z16", mode));
    ASSERT_TRUE(parsed) << parsed.error().message;
    EXPECT_EQ(parsed->colorWidth, 1280);
    EXPECT_EQ(parsed->colorHeight, 720);
    EXPECT_EQ(parsed->colorFps, 15.0);
    EXPECT_EQ(parsed->colorFourcc, v4l2::parseFourcc("MJPG"));
    EXPECT_EQ(parsed->width, 848) << "the depth mode stays";
    EXPECT_EQ(parsed->depthFourcc, V4L2_PIX_FMT_Z16);

    const auto none = withColorMode("v4l2:/dev/video3:color=none", mode);
    ASSERT_FALSE(none.ok()) << "a camera streaming no colour has no colour mode";
    EXPECT_NE(none.error().message.find("color=none"), std::string::npos) << none.error().message;
    const auto depthFormat = parseLiveSourceSpec("v4l2:/dev/video3:colorformat=Z16");
    ASSERT_FALSE(depthFormat.ok());
    EXPECT_NE(depthFormat.error().message.find("colorformat=Z16"), std::string::npos)
        << depthFormat.error().message;
    const auto badMode = parseLiveSourceSpec("v4l2:/dev/video3:colormode=640");
    ASSERT_FALSE(badMode.ok());
    EXPECT_NE(badMode.error().message.find("malformed colormode '640'"), std::string::npos)
        << badMode.error().message;
}

TEST(LiveSourceSpec, TakesATwoSensorCalibration) {
    const std::string path = writeTemp("camchain.yaml", kRigCamchain);
    for (const std::string& spec :
         {"v4l2:/dev/video3:color=/dev/video5:calib=" + path, "usb:8086:0b07:calib=" + path}) {
        auto c = parseLiveSourceSpec(spec);
        ASSERT_TRUE(c) << c.error().message;
        ASSERT_TRUE(c->calibration && c->calibration->rig) << spec;
        EXPECT_EQ(c->calibration->format, "Kalibr camchain");
        EXPECT_EQ(c->calibration->rig->depth.intrinsics.width, 640);
        EXPECT_EQ(c->calibration->rig->colour.intrinsics.width, 320);
        EXPECT_DOUBLE_EQ(c->calibration->rig->depthToColour.translationMeters[0], -0.025);
    }
    fs::remove(path);
}

TEST(LiveSourceSpec, ABadTwoSensorCalibrationIsAnErrorNamingTheField) {
    std::string text = kRigCamchain;
    text.replace(text.find("[0.0, 1.0, 0.0, 0.0]"), 20, "[0.0, 2.0, 0.0, 0.0]");
    const std::string path = writeTemp("bad-camchain.yaml", text);
    const auto c = parseLiveSourceSpec("v4l2:/dev/video3:calib=" + path);
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("cam1.T_cn_cnm1: not a rotation"), std::string::npos)
        << c.error().message;
    EXPECT_NE(c.error().message.find(path), std::string::npos) << c.error().message;
    fs::remove(path);
}

TEST(KnownCameras, ExactProductsBeforeVendorWideEntries) {
    const usb::KnownCamera* d435 = usb::findKnownCamera(0x8086, 0x0b07);
    ASSERT_TRUE(d435);
    EXPECT_FLOAT_EQ(d435->depthScaleMeters, 0.001f);
    const usb::KnownCamera* orbbec = usb::findKnownCamera(0x2bc5, 0x1234);
    ASSERT_TRUE(orbbec);
    EXPECT_FALSE(orbbec->productId);
    EXPECT_FALSE(usb::findKnownCamera(0x046d, 0x0825)) << "a webcam";
    EXPECT_FLOAT_EQ(usb::findKnownCamera(0x8086, 0x0b64)->depthScaleMeters, 0.00025f);
}

} // namespace
} // namespace dc::devices
