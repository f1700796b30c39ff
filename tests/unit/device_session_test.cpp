#include "devices/session.h"
#include "devices/synthetic/synthetic_device.h"

#include <gtest/gtest.h>

#include <semaphore>
#include <thread>

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
}

// Delivers one frame per permit the test releases and says when the capture thread asks for the next
// one, so the test knows when each delivery could have started (its release) and when the session had
// surely counted it (the capture thread is back asking).
class GatedDevice final : public Device {
public:
    std::string description() const override { return "gated test camera"; }
    Capabilities capabilities() const override { return {.sceneDepth = true}; }
    void release() { permits_.release(); }
    bool waitUntilAskedAgain() { return askedAgain_.try_acquire_for(std::chrono::seconds(10)); }

protected:
    Status doOpen() override { return {}; }
    Status doStart() override { return {}; }
    void doStop() override {}
    CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        if (std::exchange(delivered_, false))
            askedAgain_.release();
        if (!permits_.try_acquire_for(timeout))
            return {};
        delivered_ = true;
        auto f = std::make_shared<frame::Frame>();
        f->sequence = sequence_++;
        f->sceneDepth = frame::DepthData{frame::Plane<float>(4, 3, 1.0f), {}};
        return {CaptureResult::Kind::Frame, std::move(f), {}};
    }

private:
    std::counting_semaphore<> permits_{0};
    std::counting_semaphore<> askedAgain_{0};
    bool delivered_ = false; // capture thread only
    std::uint64_t sequence_ = 0;
};

TEST(Session, DeviceFpsIsTheRecentDeliveryRate) {
    using Clock = std::chrono::steady_clock;
    auto owned = std::make_unique<GatedDevice>();
    GatedDevice& device = *owned;
    Session session(std::move(owned));
    ASSERT_TRUE(session.start());
    Clock::time_point released, counted;
    const auto deliverOne = [&] {
        released = Clock::now();
        device.release();
        ASSERT_TRUE(device.waitUntilAskedAgain());
        counted = Clock::now();
    };
    for (int i = 0; i < 20; ++i) // a burst first: a lifetime average would still show it
        ASSERT_NO_FATAL_FAILURE(deliverOne());
    // Then 40 frames about 10 ms apart, more than the meter's window. Delivery i was counted between
    // release(i) and counted(i), so every interval between two deliveries lies within
    // [release(i+1) - counted(i), counted(i+1) - release(i)], and so does any average of them.
    double shortestSeconds = 1e9, longestSeconds = 0.0;
    for (int i = 0; i < 40; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        const Clock::time_point previousReleased = released, previousCounted = counted;
        ASSERT_NO_FATAL_FAILURE(deliverOne());
        shortestSeconds =
            std::min(shortestSeconds, std::chrono::duration<double>(released - previousCounted).count());
        longestSeconds =
            std::max(longestSeconds, std::chrono::duration<double>(counted - previousReleased).count());
    }
    const double fps = session.stats().deviceFps;
    EXPECT_GE(fps, 1.0 / longestSeconds);
    EXPECT_LE(fps, 1.0 / shortestSeconds);
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
