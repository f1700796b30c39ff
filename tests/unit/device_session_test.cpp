#include "devices/session.h"
#include "devices/synthetic/synthetic_device.h"

#include <gtest/gtest.h>

namespace dc::devices {
namespace {

// A source that has a camera but no depth sensor, at the device interface (the seam the foundation issue
// names): the session must refuse it with the sample's message.
class ColorOnlyDevice final : public Device {
public:
    std::string description() const override { return "color-only test camera"; }
    Capabilities capabilities() const override { return {.color = true}; }

protected:
    Status doOpen() override { return {}; }
    Status doStart() override { return {}; }
    void doStop() override {}
    CaptureResult doCapture(std::chrono::milliseconds) override { return {}; }
};

SyntheticConfig fastConfig() {
    SyntheticConfig c;
    c.depthWidth = 32;
    c.depthHeight = 24;
    c.cameraWidth = 64;
    c.cameraHeight = 48;
    c.fps = 200.0;
    return c;
}

TEST(Device, StateMachineAllowsOnlyTheDocumentedTransitions) {
    SyntheticDevice d(fastConfig());
    EXPECT_EQ(d.state(), DeviceState::Closed);
    EXPECT_FALSE(d.start()) << "cannot start a closed device";
    EXPECT_EQ(d.capture(std::chrono::milliseconds(1)).kind, CaptureResult::Kind::Error);
    ASSERT_TRUE(d.open());
    EXPECT_EQ(d.state(), DeviceState::Open);
    EXPECT_FALSE(d.open()) << "double open is refused";
    ASSERT_TRUE(d.start());
    EXPECT_EQ(d.state(), DeviceState::Streaming);
    EXPECT_EQ(d.capture(std::chrono::seconds(1)).kind, CaptureResult::Kind::Frame);
    ASSERT_TRUE(d.stop());
    EXPECT_EQ(d.state(), DeviceState::Stopped);
    ASSERT_TRUE(d.start()) << "a stopped device can stream again";
    d.close();
    EXPECT_EQ(d.state(), DeviceState::Closed);
}

TEST(Device, BadConfigurationIsAnErrorNotACrash) {
    SyntheticConfig c = fastConfig();
    c.depthWidth = 0;
    SyntheticDevice d(c);
    const Status s = d.open();
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("sizes"), std::string::npos);
    EXPECT_EQ(d.state(), DeviceState::Closed);
}

TEST(Session, DeliversFramesInOrderFromItsOwnThread) {
    Session session(std::make_unique<SyntheticDevice>(fastConfig()));
    ASSERT_TRUE(session.start());
    std::uint64_t last = 0;
    bool first = true;
    for (int i = 0; i < 10; ++i) {
        const auto frame = session.waitForFrame(std::chrono::seconds(5));
        ASSERT_TRUE(frame.has_value());
        if (!first) {
            EXPECT_GT((*frame)->sequence, last);
        }
        last = (*frame)->sequence;
        first = false;
    }
    EXPECT_EQ(session.state(), DeviceState::Streaming);
    session.stop();
    EXPECT_EQ(session.state(), DeviceState::Closed);
}

TEST(Session, ASlowConsumerSeesDropsCountedAndTheLatestFrame) {
    Session session(std::make_unique<SyntheticDevice>(fastConfig()));
    ASSERT_TRUE(session.start());
    std::this_thread::sleep_for(std::chrono::milliseconds(200)); // ~40 frames at 200 fps, none taken
    const auto frame = session.takeLatest();
    ASSERT_TRUE(frame.has_value());
    const SessionStats stats = session.stats();
    EXPECT_GT(stats.framesDropped, 5u);
    EXPECT_EQ(stats.framesDropped + 1, (*frame)->sequence + 1) << "every frame but the latest was dropped";
    EXPECT_GT(stats.deviceFps, 50.0);
}

TEST(Session, RefusesADeviceWithoutDepthWithTheSamplesMessage) {
    Session session(std::make_unique<ColorOnlyDevice>());
    const Status s = session.start();
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().message, "Unsupported device: this source provides no depth");
    EXPECT_EQ(session.state(), DeviceState::Closed);
}

TEST(Session, StartReportsADeviceThatFailsToOpen) {
    SyntheticConfig c = fastConfig();
    c.fps = -1.0;
    Session session(std::make_unique<SyntheticDevice>(c));
    const Status s = session.start();
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("frame rate"), std::string::npos);
}

} // namespace
} // namespace dc::devices
