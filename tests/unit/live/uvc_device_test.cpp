#include "base/clock.h"
#include "devices/session.h"
#include "devices/uvc/uvc_device.h"
#include "tests/unit/live/fake_v4l2.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <filesystem>

namespace dc::devices {
namespace {

using std::chrono::milliseconds;
using v4l2::testing::FakeFrame;
using v4l2::testing::FakeV4l2;
using v4l2::testing::z16Bytes;

constexpr const char* kDepth = "/dev/video0";
constexpr const char* kColor = "/dev/video1";
constexpr int kW = 8;
constexpr int kH = 6;

// The raw value of pixel i of frame s: a pattern that changes every frame, with zeros (no measurement).
std::uint16_t rawAt(int i, int s) {
    return i % 5 == 0 ? 0 : static_cast<std::uint16_t>(1000 + 37 * i + s);
}

FakeFrame depthFrame(int s) {
    std::vector<std::uint16_t> px(kW * kH);
    for (int i = 0; i < kW * kH; ++i)
        px[static_cast<std::size_t>(i)] = rawAt(i, s);
    return {z16Bytes(px)};
}

class UvcDeviceTest : public ::testing::Test {
protected:
    void SetUp() override {
        sysfs_ = std::filesystem::temp_directory_path() / ("dc-empty-sysfs-" + std::to_string(::getpid()));
        std::filesystem::create_directories(sysfs_);
        fake_.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, kW, kH, {30}}, {V4L2_PIX_FMT_Z16, 4, 3, {30}}}});
    }
    void TearDown() override { std::filesystem::remove_all(sysfs_); }

    UvcConfig config() const {
        UvcConfig c;
        c.depthNode = kDepth;
        c.sysfsRoot = sysfs_.string();
        c.depthScaleMeters = 0.001f;
        c.watchdog = milliseconds(150);
        return c;
    }

    // Captures until something other than a timeout comes back.
    CaptureResult next(Device& d) {
        for (int i = 0; i < 20; ++i) {
            CaptureResult r = d.capture(milliseconds(20));
            if (r.kind != CaptureResult::Kind::Timeout)
                return r;
        }
        return {};
    }

    static void expectPattern(const frame::Frame& f, int s) {
        const auto& depth = f.sceneDepth->depthMeters;
        ASSERT_EQ(depth.width, kW);
        for (int i = 0; i < kW * kH; ++i)
            ASSERT_EQ(depth.pixels[static_cast<std::size_t>(i)], static_cast<float>(rawAt(i, s)) * 0.001f)
                << i;
    }

    FakeV4l2 fake_;
    std::filesystem::path sysfs_;
};

TEST_F(UvcDeviceTest, ConvertsZ16ToMetersOnceWithTheDepthScale) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    EXPECT_EQ(d.depthFormat().width, kW) << "the largest size up to 1280x720 is the default";
    for (int s = 0; s < 3; ++s) {
        fake_.pushFrame(kDepth, depthFrame(s));
        const CaptureResult r = next(d);
        ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
        expectPattern(*r.frame, s);
        EXPECT_EQ(r.frame->sequence, static_cast<std::uint64_t>(s));
        EXPECT_FALSE(r.frame->sceneDepth->confidenceEstimated);
        EXPECT_TRUE(r.frame->sceneDepth->confidence.empty()) << "the sensor gave none";
        EXPECT_TRUE(r.frame->depthIntrinsics().valid());
    }
    EXPECT_TRUE(d.capabilities().approximateIntrinsics);
    d.close();
    EXPECT_EQ(fake_.openFds(), 1) << "only the wake-up eventfd, which lives as long as the device";
    EXPECT_EQ(fake_.mappings(), 0);
}

TEST_F(UvcDeviceTest, CalibrationIntrinsicsAreScaledToTheStream) {
    UvcConfig c = config();
    c.calibration = frame::Calibration{{100.0, 100.0, 8.0, 6.0, 16, 12}, "OpenCV YAML", std::nullopt, "", ""};
    UvcDevice d(c, fake_);
    ASSERT_TRUE(d.open());
    EXPECT_FALSE(d.capabilities().approximateIntrinsics);
    EXPECT_DOUBLE_EQ(d.depthIntrinsics().fx, 50.0);
    EXPECT_DOUBLE_EQ(d.depthIntrinsics().cx, 4.0);
}

TEST_F(UvcDeviceTest, EintrStormsDoNotLoseFrames) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    fake_.interruptIoctl(VIDIOC_DQBUF, 300);
    fake_.interruptIoctl(VIDIOC_QBUF, 300);
    fake_.interruptPolls(300);
    fake_.pushFrame(kDepth, depthFrame(7));
    const CaptureResult r = next(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    expectPattern(*r.frame, 7);
    EXPECT_EQ(fake_.queued(kDepth), 4u);
}

TEST_F(UvcDeviceTest, CorruptShortAndGarbageBuffersAreErrorsNotCrashes) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    FakeFrame flagged = depthFrame(0);
    flagged.flags = V4L2_BUF_FLAG_ERROR;
    FakeFrame shortFrame = depthFrame(0);
    shortFrame.bytes.resize(10);
    FakeFrame wrongBytesused = depthFrame(0);
    wrongBytesused.bytesused = 5000;
    FakeFrame garbage{std::vector<std::uint8_t>(3, 0xff)};
    for (const FakeFrame& bad : {flagged, shortFrame, wrongBytesused, garbage}) {
        fake_.pushFrame(kDepth, bad);
        const CaptureResult r = next(d);
        EXPECT_EQ(r.kind, CaptureResult::Kind::Error);
        EXPECT_FALSE(r.message.empty());
        EXPECT_EQ(d.state(), DeviceState::Streaming) << "a bad frame is dropped, the stream goes on";
    }
    fake_.pushFrame(kDepth, depthFrame(3));
    const CaptureResult r = next(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    expectPattern(*r.frame, 3);
    EXPECT_EQ(fake_.queued(kDepth), 4u) << "every dropped buffer went back to the driver";
}

TEST_F(UvcDeviceTest, AFormatChangeUnderUsRestartsTheStreamAtTheNewSize) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    const double fxBefore = d.depthIntrinsics().fx;
    fake_.changeFormat(kDepth, 4, 3);
    const CaptureResult changed = next(d);
    EXPECT_EQ(changed.kind, CaptureResult::Kind::Error);
    EXPECT_NE(changed.message.find("format changed"), std::string::npos) << changed.message;
    EXPECT_EQ(d.depthFormat().width, 4);
    EXPECT_DOUBLE_EQ(d.depthIntrinsics().fx, fxBefore / 2);
    fake_.pushFrame(kDepth, {z16Bytes(std::vector<std::uint16_t>(12, 2000))});
    const CaptureResult r = next(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    EXPECT_EQ(r.frame->sceneDepth->depthMeters.width, 4);
    EXPECT_FLOAT_EQ(r.frame->sceneDepth->depthMeters.pixels[0], 2.0f);
    EXPECT_EQ(fake_.mappings(), 4) << "the old buffers were released";
}

TEST_F(UvcDeviceTest, UnplugIsDisconnectedWithNothingLeftOpenAndReplugReconnects) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    fake_.unplug(kDepth);
    const CaptureResult r = next(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Disconnected);
    EXPECT_EQ(d.state(), DeviceState::Disconnected);
    EXPECT_EQ(fake_.mappings(), 0);
    EXPECT_EQ(fake_.openFds(), 1) << "only the wake-up eventfd stays";
    EXPECT_FALSE(d.reconnect()) << "still unplugged";
    EXPECT_EQ(d.state(), DeviceState::Disconnected);
    fake_.replug(kDepth);
    ASSERT_TRUE(d.reconnect());
    EXPECT_EQ(d.state(), DeviceState::Streaming);
    fake_.pushFrame(kDepth, depthFrame(11));
    const CaptureResult again = next(d);
    ASSERT_EQ(again.kind, CaptureResult::Kind::Frame) << again.message;
    expectPattern(*again.frame, 11);
}

TEST_F(UvcDeviceTest, TheWatchdogReportsAStallAndAFrameEndsIt) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    const CaptureResult stalled = next(d);
    ASSERT_EQ(stalled.kind, CaptureResult::Kind::Stalled);
    EXPECT_NE(stalled.message.find("watchdog"), std::string::npos);
    EXPECT_EQ(d.state(), DeviceState::Stalled);
    EXPECT_EQ(d.capture(milliseconds(5)).kind, CaptureResult::Kind::Timeout) << "reported once";
    fake_.pushFrame(kDepth, depthFrame(1));
    ASSERT_EQ(next(d).kind, CaptureResult::Kind::Frame);
    EXPECT_EQ(d.state(), DeviceState::Streaming);
}

TEST_F(UvcDeviceTest, DepthAndColorNodesArePairedByTimestamp) {
    fake_.addNode(kColor, {.modes = {{V4L2_PIX_FMT_YUYV, kW, kH, {30}}}});
    UvcConfig c = config();
    c.colorNode = kColor;
    UvcDevice d(c, fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    ASSERT_EQ(d.colorNodePath(), kColor);
    const std::int64_t t0 = base::monotonicNowNs() / 1000 * 1000; // V4L2 timestamps have microseconds
    FakeFrame depth = depthFrame(0);
    depth.timestampNs = t0;
    FakeFrame color{std::vector<std::uint8_t>(kW * kH * 2, 0x55)};
    color.timestampNs = t0 + 2'000'000; // 2 ms apart: the same moment at 30 fps
    fake_.pushFrame(kDepth, depth);
    fake_.pushFrame(kColor, color);
    const CaptureResult r = next(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    ASSERT_FALSE(r.frame->capturedImage.empty());
    EXPECT_EQ(r.frame->capturedImage.format, frame::PixelFormat::Yuyv);
    EXPECT_EQ((*r.frame->capturedImage.bytes)[0], 0x55);
    EXPECT_EQ(r.frame->timestampNs, t0);
    EXPECT_EQ(d.pairer().paired(), 1u);
    // Each stream's own driver sequence and stamp; the fake driver marks the end of the frame (EOF).
    EXPECT_EQ(r.frame->timing.depth.sensorNs, t0);
    ASSERT_TRUE(r.frame->timing.colour);
    EXPECT_EQ(r.frame->timing.colour->driverSequence, 0u);
    EXPECT_EQ(r.frame->timing.colour->sensorNs, t0 + 2'000'000);
    EXPECT_EQ(r.frame->timing.colour->source, frame::TimestampSource::EndOfFrame);
}

// The driver's sequence counts the buffer it returned marked corrupted too, so the frames after it show
// the gap; the timestamp's source is what the buffer's flags say.
TEST_F(UvcDeviceTest, EachFrameCarriesTheDriversSequenceAndWhatItsTimestampMarks) {
    UvcDevice d(config(), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    const std::int64_t t0 = base::monotonicNowNs() / 1000 * 1000; // V4L2 timestamps have microseconds
    FakeFrame first = depthFrame(0);
    first.flags = V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
    first.timestampNs = t0;
    FakeFrame corrupt = depthFrame(1);
    corrupt.flags = V4L2_BUF_FLAG_ERROR | V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
    FakeFrame third = depthFrame(2);
    third.flags = V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
    third.timestampNs = t0 + 66'000'000;
    FakeFrame endOfFrame = depthFrame(3);
    for (const FakeFrame& f : {first, corrupt, third, endOfFrame})
        fake_.pushFrame(kDepth, f);
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < 8 && frames.size() < 3; ++i)
        if (CaptureResult r = next(d); r.kind == CaptureResult::Kind::Frame)
            frames.push_back(r.frame);
    ASSERT_EQ(frames.size(), 3u);
    EXPECT_EQ(frames[0]->timing.depth.driverSequence, 0u);
    EXPECT_EQ(frames[1]->timing.depth.driverSequence, 2u) << "the corrupted buffer was sequence 1";
    EXPECT_EQ(frames[2]->timing.depth.driverSequence, 3u);
    EXPECT_EQ(frames[0]->timing.depth.sensorNs, t0);
    EXPECT_EQ(frames[1]->timing.depth.sensorNs, t0 + 66'000'000);
    EXPECT_EQ(frames[0]->timing.depth.source, frame::TimestampSource::StartOfExposure);
    EXPECT_EQ(frames[1]->timing.depth.source, frame::TimestampSource::StartOfExposure);
    EXPECT_EQ(frames[2]->timing.depth.source, frame::TimestampSource::EndOfFrame);
    for (const frame::FramePtr& f : frames) {
        EXPECT_TRUE(f->timing.depth.monotonic);
        EXPECT_FALSE(f->timing.colour) << "no colour node";
    }
}

TEST_F(UvcDeviceTest, ASessionReconnectsByItselfAndReportsEachState) {
    Session session(std::make_unique<UvcDevice>(config(), fake_));
    ASSERT_TRUE(session.start());
    fake_.pushFrame(kDepth, depthFrame(0));
    ASSERT_TRUE(session.waitForFrame(std::chrono::seconds(2)));
    fake_.unplug(kDepth);
    for (int i = 0; i < 100 && session.state() != DeviceState::Disconnected; ++i)
        std::this_thread::sleep_for(milliseconds(10));
    EXPECT_EQ(session.state(), DeviceState::Disconnected);
    fake_.replug(kDepth);
    for (int i = 0; i < 300 && session.state() != DeviceState::Streaming; ++i)
        std::this_thread::sleep_for(milliseconds(10));
    ASSERT_EQ(session.state(), DeviceState::Streaming) << "reconnected without a restart";
    fake_.pushFrame(kDepth, depthFrame(5));
    const auto frame = session.waitForFrame(std::chrono::seconds(2));
    ASSERT_TRUE(frame.has_value());
    std::vector<std::pair<DeviceState, std::string>> states;
    for (const SessionEvent& e : session.drainEvents())
        if (e.kind == SessionEvent::Kind::StateChanged)
            states.emplace_back(e.state, e.message);
    ASSERT_GE(states.size(), 3u);
    EXPECT_EQ(states[0].first, DeviceState::Streaming);
    EXPECT_EQ(states[0].second, kApproximateIntrinsicsMessage)
        << "the UI learns that geometry is approximate";
    EXPECT_EQ(states[1].first, DeviceState::Disconnected);
    EXPECT_EQ(states.back().first, DeviceState::Streaming);
    EXPECT_GT(session.stats().latencyMs, 0.0);
    session.stop();
    EXPECT_EQ(fake_.mappings(), 0);
}

TEST_F(UvcDeviceTest, ASessionShowsAStallAndItsEnd) {
    Session session(std::make_unique<UvcDevice>(config(), fake_));
    ASSERT_TRUE(session.start());
    for (int i = 0; i < 100 && session.state() != DeviceState::Stalled; ++i)
        std::this_thread::sleep_for(milliseconds(10));
    EXPECT_EQ(session.state(), DeviceState::Stalled);
    fake_.pushFrame(kDepth, depthFrame(0));
    ASSERT_TRUE(session.waitForFrame(std::chrono::seconds(2)));
    EXPECT_EQ(session.state(), DeviceState::Streaming);
}

TEST_F(UvcDeviceTest, StopWakesTheCaptureThreadAndLeavesNothingOpen) {
    {
        Session session(std::make_unique<UvcDevice>(config(), fake_));
        ASSERT_TRUE(session.start());
        session.stop();
        EXPECT_EQ(session.state(), DeviceState::Closed);
    }
    EXPECT_EQ(fake_.openFds(), 0);
    EXPECT_EQ(fake_.mappings(), 0);
}

TEST_F(UvcDeviceTest, ANodeWithoutDepthFormatsIsRefusedWithAReason) {
    fake_.addNode(kColor, {.modes = {{V4L2_PIX_FMT_YUYV, kW, kH, {30}}}});
    UvcConfig c = config();
    c.depthNode = kColor;
    UvcDevice d(c, fake_);
    const Status s = d.open();
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("Z16"), std::string::npos) << s.error().message;
    EXPECT_EQ(fake_.openFds(), 1);
}

// ---- two sensors ----------------------------------------------------------------------------------

// A depth sensor of this fixture's 8x6 and a colour sensor calibrated at 16x12, 25 mm apart.
frame::Calibration rigCalibration(int colourWidth = 16, int colourHeight = 12) {
    frame::RigCalibration rig;
    rig.depth.intrinsics = {10.0, 10.0, 3.5, 2.5, kW, kH};
    rig.colour.intrinsics = {18.0, 18.0, 7.5, 5.5, colourWidth, colourHeight};
    rig.depthToColour.translationMeters = {-0.025, 0.0, 0.0};
    rig.name = "rig.yaml (Kalibr camchain)";
    return {rig.colour.intrinsics, "Kalibr camchain", rig, "cam0.resolution", "cam1.resolution"};
}

class UvcRigTest : public UvcDeviceTest {
protected:
    void SetUp() override {
        UvcDeviceTest::SetUp();
        // The depth size first would be today's choice; the calibrated 16x12 must win. 12x4 is of another
        // shape than the calibration.
        fake_.addNode(kColor, {.modes = {{V4L2_PIX_FMT_YUYV, kW, kH, {30}},
                                         {V4L2_PIX_FMT_YUYV, 16, 12, {30}},
                                         {V4L2_PIX_FMT_YUYV, 12, 4, {30}}}});
    }

    UvcConfig rigConfig(std::optional<frame::Calibration> calibration) const {
        UvcConfig c = config();
        c.colorNode = kColor;
        c.calibration = std::move(calibration);
        return c;
    }

    // One depth frame and the colour frame taken with it.
    CaptureResult pairedFrame(UvcDevice& d) {
        const std::int64_t t0 = base::monotonicNowNs() / 1000 * 1000;
        FakeFrame depth = depthFrame(0);
        depth.timestampNs = t0;
        FakeFrame color{std::vector<std::uint8_t>(
            static_cast<std::size_t>(d.colorFormat().width) * d.colorFormat().height * 2, 0x55)};
        color.timestampNs = t0 + 1'000'000;
        fake_.pushFrame(kDepth, depth);
        fake_.pushFrame(kColor, color);
        return next(d);
    }
};

TEST_F(UvcRigTest, ATwoSensorCalibrationRidesWithEveryPairedFrame) {
    const frame::Calibration calibration = rigCalibration();
    UvcDevice d(rigConfig(calibration), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    EXPECT_EQ(d.colorFormat().width, 16) << "the size the colour sensor was calibrated at";
    EXPECT_FALSE(d.capabilities().unregisteredColour);
    EXPECT_FALSE(d.capabilities().approximateIntrinsics);
    const CaptureResult r = pairedFrame(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    ASSERT_TRUE(r.frame->rig);
    EXPECT_EQ(r.frame->rig, d.rig());
    EXPECT_EQ(r.frame->rig->depthToColour, calibration.rig->depthToColour);
    EXPECT_EQ(r.frame->cameraIntrinsics, calibration.rig->colour.intrinsics) << "the colour sensor's";
    EXPECT_EQ(r.frame->depthIntrinsics(), calibration.rig->depth.intrinsics) << "the depth sensor's";
    EXPECT_EQ(r.frame->capturedImage.width, 16);
}

TEST_F(UvcRigTest, StreamsThatDoNotFitTheCalibrationAreRefusedNamingItsField) {
    UvcDevice d(rigConfig(rigCalibration(20, 10)), fake_); // no 2:1 colour mode is offered
    const Status s = d.open();
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("calibration cam1.resolution 20x10 does not fit the colour stream's"),
              std::string::npos)
        << s.error().message;
    EXPECT_NE(s.error().message.find("rig.yaml"), std::string::npos) << s.error().message;
    EXPECT_EQ(fake_.openFds(), 1) << "nothing left open but the wake-up eventfd";
}

// The colour node changing size under us: the same shape keeps the calibration (scaled), another shape
// cannot be registered and ends the stream with the calibration's field named.
TEST_F(UvcRigTest, AColourSizeChangeKeepsTheRigOnlyWhileItFits) {
    const frame::Calibration calibration = rigCalibration();
    UvcDevice d(rigConfig(calibration), fake_);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    fake_.changeFormat(kColor, 8, 6);
    EXPECT_EQ(next(d).kind, CaptureResult::Kind::Error) << "restarted at the new size";
    const CaptureResult r = pairedFrame(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    ASSERT_TRUE(r.frame->rig);
    EXPECT_EQ(r.frame->cameraIntrinsics, calibration.rig->colour.intrinsics.scaledTo(8, 6));
    fake_.changeFormat(kColor, 12, 4);
    const CaptureResult refused = next(d);
    EXPECT_EQ(refused.kind, CaptureResult::Kind::Disconnected);
    EXPECT_NE(refused.message.find("cam1.resolution 16x12 does not fit the colour stream's 12x4"),
              std::string::npos)
        << refused.message;
}

// A colour mode asked for (the window's list) wins over the calibrated size while it fits the calibration;
// one of another shape is refused naming the calibration's field, and one not offered names the node.
TEST_F(UvcRigTest, AColourModeAskedForStreamsOnlyWhereItFitsTheCalibration) {
    UvcConfig c = rigConfig(rigCalibration());
    c.colorFourcc = V4L2_PIX_FMT_YUYV;
    c.colorWidth = kW;
    c.colorHeight = kH;
    UvcDevice scaled(c, fake_);
    ASSERT_TRUE(scaled.open());
    EXPECT_EQ(scaled.colorFormat().width, kW) << "the mode asked for, not the calibrated 16x12";
    EXPECT_EQ(scaled.colorFormat().height, kH);
    scaled.close();

    c.colorWidth = 12;
    c.colorHeight = 4;
    UvcDevice otherShape(c, fake_);
    const Status refused = otherShape.open();
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("cam1.resolution 16x12 does not fit the colour stream's 12x4"),
              std::string::npos)
        << refused.error().message;

    c.colorWidth = 20;
    c.colorHeight = 10;
    UvcDevice notOffered(c, fake_);
    const Status missing = notOffered.open();
    ASSERT_FALSE(missing) << "not streamed without colour behind the person's back";
    EXPECT_NE(missing.error().message.find(kColor), std::string::npos) << missing.error().message;
    EXPECT_EQ(fake_.openFds(), 3) << "only the three devices' wake-up eventfds";
}

// What the window's Colour mode list offers: the colour node's image modes, none of the depth node's.
TEST_F(UvcRigTest, TheColourNodesModesAreListedApartFromTheDepthNodes) {
    fake_.addNode(kColor,
                  {.modes = {{V4L2_PIX_FMT_YUYV, 16, 12, {30, 15}}, {V4L2_PIX_FMT_MJPEG, 32, 24, {30}}}});
    const auto controls = UvcDevice(rigConfig(std::nullopt), fake_).sensorControls();
    ASSERT_TRUE(controls);
    EXPECT_EQ(
        controls->colorModes(),
        (std::vector<StreamMode>{{"YUYV", 16, 12, 30.0}, {"YUYV", 16, 12, 15.0}, {"MJPG", 32, 24, 30.0}}));
    EXPECT_EQ(controls->depthModes(), (std::vector<StreamMode>{{"Z16", kW, kH, 30.0}, {"Z16", 4, 3, 30.0}}));
    UvcConfig depthOnly = config();
    depthOnly.color = false;
    EXPECT_TRUE(UvcDevice(depthOnly, fake_).sensorControls()->colorModes().empty());
}

TEST_F(UvcRigTest, ColourWithoutATwoSensorCalibrationIsSaidToBeUnregistered) {
    frame::Calibration single = rigCalibration();
    single.rig.reset();
    single.intrinsics = {10.0, 10.0, 3.5, 2.5, kW, kH};
    UvcDevice d(rigConfig(single), fake_);
    EXPECT_TRUE(d.capabilities().unregisteredColour);
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    const CaptureResult r = pairedFrame(d);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    EXPECT_FALSE(r.frame->rig);
    EXPECT_EQ(r.frame->depthIntrinsics(), single.intrinsics) << "one camera: the file's intrinsics";
    UvcConfig depthOnly = rigConfig(std::nullopt);
    depthOnly.color = false;
    EXPECT_FALSE(UvcDevice(depthOnly, fake_).capabilities().unregisteredColour) << "no colour at all";
}

} // namespace
} // namespace dc::devices
