// UvcDevice streams the depth node's metadata node (uvcvideo's second node per streaming interface) beside
// it: V4L2_META_FMT_D4XX for a camera the known-camera table marks as a D4xx when the node offers it, else
// V4L2_META_FMT_UVC; each depth frame carries what the metadata buffer of its sequence says, and the video
// never waits for, or fails with, the metadata. The fake serves the node's buffers built byte by byte.

#include "base/clock.h"
#include "base/log.h"
#include "devices/uvc/metadata_stream.h"
#include "devices/uvc/uvc_device.h"
#include "tests/unit/live/fake_v4l2.h"
#include "tests/unit/metadata_bytes.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <unistd.h>

namespace dc::devices::metadata_stream_test {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using v4l2::testing::FakeFrame;
using v4l2::testing::FakeV4l2;
using v4l2::testing::metadataNodeSpec;
using v4l2::testing::z16Bytes;

constexpr const char* kDepth = "/dev/video0";
constexpr const char* kMeta = "/dev/video1";
constexpr const char* kColor = "/dev/video2";
constexpr int kW = 8;
constexpr int kH = 6;
constexpr std::uint32_t kPts = 123456;
constexpr std::uint32_t kScr = 123999;
constexpr std::uint16_t kSofToken = 0x0123;

using dc::test::MetadataBytes;

// One block: the driver's clock and USB frame number, then the camera's header with PTS and SCR (end of
// header, PTS, SCR, end of frame) and `vendor` bytes after it.
std::vector<std::uint8_t> payloadHeader(const std::vector<std::uint8_t>& vendor = {}) {
    return MetadataBytes{}
        .u64(1'000'000'000)
        .u16(0x0345)
        .u8(12 + vendor.size())
        .u8(0x80 | 0x04 | 0x08 | 0x02)
        .u32(kPts)
        .u32(kScr)
        .u16(kSofToken)
        .append(vendor)
        .bytes;
}

// A D435's depth metadata: Intel's capture timing block (frame counter) and depth control block (gain,
// exposure, laser power), every field marked valid.
std::vector<std::uint8_t> d4xxBuffer(std::uint32_t exposureUs, std::uint32_t frameCounter = 4242) {
    const std::vector<std::uint8_t> timing = MetadataBytes{}
                                                 .u32(0x80000001)
                                                 .u32(40)
                                                 .u32(1)
                                                 .u32(0xffffffff)
                                                 .u32(frameCounter)
                                                 .u32(4250)
                                                 .u32(9000)
                                                 .u32(exposureUs)
                                                 .u32(33333)
                                                 .u32(2000)
                                                 .bytes;
    MetadataBytes control;
    control.u32(0x80000000).u32(60).u32(3).u32(0xffffffff).u32(16).u32(exposureUs).u32(150);
    for (int i = 0; i < 7; ++i)
        control.u32(0);
    control.u32(0);
    return payloadHeader(MetadataBytes{}.append(timing).append(control.bytes).bytes);
}

FakeFrame metadataFrame(std::uint32_t sequence, std::vector<std::uint8_t> bytes) {
    FakeFrame f{std::move(bytes)};
    f.sequence = sequence;
    return f;
}

FakeFrame depthFrame(std::uint16_t value = 1000) {
    return {z16Bytes(std::vector<std::uint16_t>(kW * kH, value))};
}

// The warnings logged while it lives.
class LoggedWarnings {
public:
    LoggedWarnings() {
        token_ = setLogSink([this](LogLevel level, const std::string& message) {
            std::lock_guard lock(mutex_);
            if (level == LogLevel::Warning)
                messages_.push_back(message);
        });
        std::lock_guard lock(mutex_);
        messages_.clear(); // what was logged before
    }
    ~LoggedWarnings() { removeLogSink(token_); }
    int containing(const std::string& text) const {
        std::lock_guard lock(mutex_);
        return static_cast<int>(std::count_if(messages_.begin(), messages_.end(), [&](const std::string& m) {
            return m.find(text) != std::string::npos;
        }));
    }

private:
    mutable std::mutex mutex_;
    std::vector<std::string> messages_;
    std::uint64_t token_ = 0;
};

class UvcMetadataStream : public ::testing::Test {
protected:
    void SetUp() override {
        sysfs_ = fs::temp_directory_path() / ("dc-meta-sysfs-" + std::to_string(::getpid()));
        fs::remove_all(sysfs_);
        fs::create_directories(sysfs_ / "class/video4linux/video0");
        fake_.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, kW, kH, {30}}}});
    }
    void TearDown() override { fs::remove_all(sysfs_); }

    // The depth node's USB device in sysfs, as UvcDevice finds it behind a v4l2: node.
    void plugUsb(const char* vendor, const char* product) {
        const fs::path device = sysfs_ / "bus/usb/devices/1-1";
        fs::create_directories(device / "1-1:1.0");
        std::ofstream(device / "idVendor") << vendor << "\n";
        std::ofstream(device / "idProduct") << product << "\n";
        fs::create_directory_symlink(device / "1-1:1.0", sysfs_ / "class/video4linux/video0/device");
    }

    UvcConfig config() const {
        UvcConfig c;
        c.depthNode = kDepth;
        c.color = false;
        c.sysfsRoot = sysfs_.string();
        c.depthScaleMeters = 0.001f;
        c.watchdog = milliseconds(2000);
        return c;
    }

    // Captures until something other than a timeout comes back.
    static CaptureResult next(Device& d) {
        for (int i = 0; i < 20; ++i) {
            CaptureResult r = d.capture(milliseconds(20));
            if (r.kind != CaptureResult::Kind::Timeout)
                return r;
        }
        return {};
    }

    // The next frame, which must come.
    static frame::FramePtr nextFrame(Device& d) {
        const CaptureResult r = next(d);
        EXPECT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
        return r.frame ? r.frame : std::make_shared<frame::Frame>();
    }

    FakeV4l2 fake_;
    fs::path sysfs_;
};

TEST_F(UvcMetadataStream, AD435sFramesCarryTheExposureOfTheMetadataOfTheirSequence) {
    plugUsb("8086", "0b07");
    fake_.addNode(kMeta, metadataNodeSpec({V4L2_META_FMT_UVC, V4L2_META_FMT_D4XX}));
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    EXPECT_EQ(d.metadataNodePath(), kMeta);
    EXPECT_EQ(d.metadataFormat(), V4L2_META_FMT_D4XX) << "a D4xx's, though UVC is listed first";
    EXPECT_EQ(fake_.currentFormat(kMeta), V4L2_META_FMT_D4XX);
    EXPECT_TRUE(fake_.streaming(kMeta));

    // The metadata comes first and is taken while no frame is there yet.
    fake_.pushFrame(kMeta, metadataFrame(0, d4xxBuffer(8500, 77)));
    EXPECT_EQ(d.capture(milliseconds(20)).kind, CaptureResult::Kind::Timeout);
    fake_.pushFrame(kDepth, depthFrame());
    const frame::FramePtr first = nextFrame(d);
    EXPECT_EQ(first->timing.depth.exposureUs, 8500u);
    const frame::CameraMetadata& m = first->timing.depthMetadata;
    EXPECT_EQ(m.frameCounter, 77u);
    EXPECT_EQ(m.gain, 16u);
    EXPECT_EQ(m.laserPowerMw, 150u);
    EXPECT_EQ(m.ptsTicks, kPts);
    EXPECT_EQ(m.scrTicks, kScr);
    EXPECT_EQ(m.scrUsbFrame, kSofToken);

    // No metadata buffer for sequence 1: that frame has none, and it is not held for one.
    fake_.pushFrame(kDepth, depthFrame());
    const frame::FramePtr second = nextFrame(d);
    EXPECT_EQ(second->timing.depth.driverSequence, 1u);
    EXPECT_FALSE(second->timing.depth.exposureUs);
    EXPECT_FALSE(second->timing.depthMetadata.frameCounter);
    EXPECT_FALSE(second->timing.depthMetadata.ptsTicks);

    // Metadata late for sequence 1 (its frame went out) and out of order for 3 and 2; the video buffer
    // before its metadata on the fake's queues: each frame gets its own sequence's.
    fake_.pushFrame(kDepth, depthFrame());
    fake_.pushFrame(kDepth, depthFrame());
    fake_.pushFrame(kMeta, metadataFrame(1, d4xxBuffer(1111)));
    fake_.pushFrame(kMeta, metadataFrame(3, d4xxBuffer(3333)));
    fake_.pushFrame(kMeta, metadataFrame(2, d4xxBuffer(2222)));
    const frame::FramePtr third = nextFrame(d);
    const frame::FramePtr fourth = nextFrame(d);
    EXPECT_EQ(third->timing.depth.driverSequence, 2u);
    EXPECT_EQ(third->timing.depth.exposureUs, 2222u);
    EXPECT_EQ(fourth->timing.depth.driverSequence, 3u);
    EXPECT_EQ(fourth->timing.depth.exposureUs, 3333u);
    EXPECT_EQ(fake_.queued(kMeta), 4u) << "every metadata buffer went back to the driver";
    d.close();
    EXPECT_EQ(fake_.openFds(), 1) << "only the wake-up eventfd";
    EXPECT_EQ(fake_.mappings(), 0);
}

// A depth frame waiting for its colour frame takes the metadata that came after its video buffer.
TEST_F(UvcMetadataStream, MetadataArrivingAfterItsVideoBufferStillMatchesAFrameNotYetOut) {
    plugUsb("8086", "0b07");
    fake_.addNode(kMeta, metadataNodeSpec({V4L2_META_FMT_D4XX, V4L2_META_FMT_UVC}));
    fake_.addNode(kColor, {.modes = {{V4L2_PIX_FMT_YUYV, kW, kH, {30}}}});
    UvcConfig c = config();
    c.color = true;
    c.colorNode = kColor;
    UvcDevice d(c, fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    ASSERT_EQ(d.colorNodePath(), kColor);
    const std::int64_t t0 = base::monotonicNowNs() / 1000 * 1000;
    FakeFrame depth = depthFrame();
    depth.timestampNs = t0;
    fake_.pushFrame(kDepth, depth);
    EXPECT_EQ(d.capture(milliseconds(20)).kind, CaptureResult::Kind::Timeout) << "waits for its colour";
    fake_.pushFrame(kMeta, metadataFrame(0, d4xxBuffer(9000)));
    EXPECT_EQ(d.capture(milliseconds(20)).kind, CaptureResult::Kind::Timeout);
    FakeFrame color{std::vector<std::uint8_t>(kW * kH * 2, 0x55)};
    color.timestampNs = t0 + 1'000'000;
    fake_.pushFrame(kColor, color);
    const frame::FramePtr f = nextFrame(d);
    EXPECT_FALSE(f->capturedImage.empty());
    EXPECT_EQ(f->timing.depth.exposureUs, 9000u);
}

TEST_F(UvcMetadataStream, ABadMetadataBufferLeavesItsFrameWithoutAndIsLoggedOnce) {
    plugUsb("8086", "0b07");
    fake_.addNode(kMeta, metadataNodeSpec({V4L2_META_FMT_D4XX, V4L2_META_FMT_UVC}));
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    const LoggedWarnings warnings;
    std::vector<std::uint8_t> cut = d4xxBuffer(5000);
    cut.resize(cut.size() - 3); // the depth control block runs past the buffer
    FakeFrame flagged = metadataFrame(2, d4xxBuffer(6000));
    flagged.flags = V4L2_BUF_FLAG_ERROR;
    fake_.pushFrame(kMeta, metadataFrame(0, std::vector<std::uint8_t>(5, 0xff)));
    fake_.pushFrame(kMeta, metadataFrame(1, cut));
    fake_.pushFrame(kMeta, flagged);
    fake_.pushFrame(kMeta, metadataFrame(3, d4xxBuffer(7000)));
    for (int i = 0; i < 4; ++i)
        fake_.pushFrame(kDepth, depthFrame());
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < 4; ++i)
        frames.push_back(nextFrame(d));
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(frames[i]->timing.depth.driverSequence, static_cast<std::uint32_t>(i));
        EXPECT_FALSE(frames[i]->timing.depth.exposureUs) << i;
        EXPECT_FALSE(frames[i]->timing.depthMetadata.ptsTicks) << i;
    }
    EXPECT_EQ(frames[3]->timing.depth.exposureUs, 7000u) << "the stream goes on";
    EXPECT_EQ(d.state(), DeviceState::Streaming);
    EXPECT_EQ(warnings.containing("metadata buffer skipped"), 1) << "rate-limited";
    EXPECT_EQ(fake_.queued(kMeta), 4u) << "bad buffers went back to the driver too";
}

// V4L2_META_FMT_UVC for every camera not marked as a D4xx, even where the node lists D4XX first, and for
// a D4xx whose node does not offer D4XX: the frames carry the payload header's clocks, no exposure.
TEST_F(UvcMetadataStream, AnyOtherCameraGetsTheUvcFormatAndStillStreams) {
    for (int camera = 0; camera < 3; ++camera) {
        fs::remove_all(sysfs_ / "bus");
        fs::remove(sysfs_ / "class/video4linux/video0/device");
        std::vector<std::uint32_t> offered{V4L2_META_FMT_D4XX, V4L2_META_FMT_UVC};
        if (camera == 1)
            plugUsb("2bc5", "0401"); // an Orbbec; camera 0 is on no USB bus
        if (camera == 2) {
            plugUsb("8086", "0b07");
            offered = {V4L2_META_FMT_UVC};
        }
        FakeV4l2 fake;
        fake.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, kW, kH, {30}}}});
        fake.addNode(kMeta, metadataNodeSpec(offered));
        UvcDevice d(config(), fake);
        ASSERT_TRUE(d.open());
        ASSERT_TRUE(d.start());
        EXPECT_EQ(d.metadataFormat(), V4L2_META_FMT_UVC) << camera;
        EXPECT_EQ(fake.currentFormat(kMeta), V4L2_META_FMT_UVC) << camera;
        fake.pushFrame(kMeta, metadataFrame(0, payloadHeader()));
        fake.pushFrame(kDepth, depthFrame());
        const frame::FramePtr f = nextFrame(d);
        EXPECT_EQ(f->timing.depthMetadata.ptsTicks, kPts) << camera;
        EXPECT_EQ(f->timing.depthMetadata.scrTicks, kScr) << camera;
        EXPECT_FALSE(f->timing.depth.exposureUs) << camera;
        EXPECT_FALSE(f->timing.depthMetadata.frameCounter) << camera;
        fake.pushFrame(kDepth, depthFrame());
        EXPECT_FALSE(nextFrame(d)->timing.depthMetadata.ptsTicks) << "no metadata buffer for sequence 1";
    }
}

// A metadata node that cannot stream, or that goes away, leaves the camera streaming without it, and
// says so once.
TEST_F(UvcMetadataStream, AMetadataNodeThatFailsLeavesTheVideoStreaming) {
    fake_.addNode(kMeta, metadataNodeSpec({V4L2_META_FMT_UVC}));
    {
        const LoggedWarnings warnings;
        fake_.failIoctl(VIDIOC_STREAMON, -EIO); // the metadata node starts first
        UvcDevice d(config(), fake_);
        ASSERT_TRUE(d.open());
        ASSERT_TRUE(d.start());
        EXPECT_FALSE(fake_.streaming(kMeta));
        EXPECT_TRUE(fake_.streaming(kDepth));
        EXPECT_EQ(d.metadataNodePath(), "");
        EXPECT_EQ(d.metadataFormat(), 0u);
        fake_.pushFrame(kDepth, depthFrame());
        EXPECT_FALSE(nextFrame(d)->timing.depthMetadata.ptsTicks);
        EXPECT_EQ(warnings.containing("streaming without the camera's metadata"), 1);
        EXPECT_EQ(fake_.mappings(), 4) << "only the depth node's buffers";
    }
    const LoggedWarnings warnings;
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    ASSERT_TRUE(fake_.streaming(kMeta));
    fake_.pushFrame(kMeta, metadataFrame(0, payloadHeader()));
    FakeFrame restarted = depthFrame(); // a driver counts again from 0 at each start; the fake does not
    restarted.sequence = 0;
    fake_.pushFrame(kDepth, restarted);
    EXPECT_EQ(nextFrame(d)->timing.depthMetadata.ptsTicks, kPts);
    fake_.unplug(kMeta);
    for (std::uint16_t i = 0; i < 3; ++i) {
        fake_.pushFrame(kDepth, depthFrame(i));
        const frame::FramePtr f = nextFrame(d);
        EXPECT_EQ(f->timing.depth.driverSequence, i + 1u);
        EXPECT_FALSE(f->timing.depthMetadata.ptsTicks);
    }
    EXPECT_EQ(d.state(), DeviceState::Streaming);
    EXPECT_EQ(warnings.containing("streaming without the camera's metadata"), 1);
}

TEST(MetadataWindow, MatchesBySequenceAcrossTheWrapAndDropsWhatIsStale) {
    MetadataWindow w;
    const auto with = [](std::uint32_t exposure) { return FrameMetadata{exposure, {}}; };
    w.add(0xffffffffu, with(1));
    w.add(0, with(2));
    w.add(1, with(3));
    EXPECT_FALSE(w.take(0xfffffffeu)) << "none for it; it is older than all";
    EXPECT_EQ(w.size(), 3u);
    ASSERT_TRUE(w.take(0));
    EXPECT_EQ(w.size(), 1u) << "0xffffffff is older than 0 and went with it";
    w.add(0, with(4));
    EXPECT_EQ(w.size(), 1u) << "sequence 0's frame is out";
    EXPECT_EQ(w.take(1)->exposureUs, 3u);
    for (std::uint32_t s = 2; s < 2 + MetadataWindow::kSize + 3; ++s)
        w.add(s, with(s));
    EXPECT_EQ(w.size(), MetadataWindow::kSize);
    EXPECT_FALSE(w.take(2)) << "the oldest fell out of the window";
}

} // namespace
} // namespace dc::devices::metadata_stream_test
