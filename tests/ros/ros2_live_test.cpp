// The live ros2: source against a ROS 2 camera on the other DDS implementation: depthcloud subscribes through
// Cyclone DDS, the camera (publish_camera_dds) publishes through Fast DDS with ROS 2's wire names, on a
// domain of the test's own, over 127.0.0.1 only (both sides discover each other by unicast). Every frame is
// checked pixel for pixel against camera_pattern.h. Also the spec grammar and what bad input does.

#include "devices/ros/dds_subscription.h"
#include "devices/ros/ros_device.h"
#include "devices/ros/ros_source_spec.h"
#include "devices/session.h"
#include "devices/source_spec.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/camera_checks.h"
#include "tests/ros/ros_processes.h"
#include "tests/ros/shell_run.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>
#include <unistd.h>

// Its own namespace: the unity build compiles it with ros_live_test.cpp, whose names it would repeat.
namespace dc::devices::ros::dds_test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::camera::frameIndex;

constexpr int kWidth = 848, kHeight = 480;
constexpr const char* kDepthTopic = "/camera/camera/depth/image_rect_raw";
// Cyclone DDS on 127.0.0.1 alone, finding its peers there by unicast (the loopback interface has no
// multicast).
constexpr const char* kLoopbackConfig =
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
    "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>";

// Each test runs in its own process (gtest_discover_tests): a domain of its own keeps tests that run at the
// same time apart.
int testDomain() {
    return 1 + static_cast<int>(getpid() % kMaxRosDomain);
}

TEST(Ros2SourceSpec, FindsColourAndCameraInfoAsTheRos2WrapperNamesThem) {
    auto config = parseRos2SourceSpec(kDepthTopic);
    ASSERT_TRUE(config) << config.error().message;
    EXPECT_TRUE(config->ros2);
    EXPECT_EQ(config->colorTopic, "/camera/camera/color/image_raw");
    EXPECT_EQ(config->infoTopic, "/camera/camera/depth/camera_info");
    EXPECT_EQ(config->domain, -1);
    EXPECT_EQ(ddsTopicName(kDepthTopic), "rt/camera/camera/depth/image_rect_raw");
}

TEST(Ros2SourceSpec, ParsesTheDomainAndRefusesWhatIsNotRos2sNamingTheOption) {
    auto config = parseRos2SourceSpec(std::string(kDepthTopic) + ":domain=42:tolerance=5:frame=odom");
    ASSERT_TRUE(config) << config.error().message;
    EXPECT_EQ(config->domain, 42);
    EXPECT_EQ(config->pairTolerance, 5ms);
    EXPECT_EQ(config->fixedFrame, "odom");
    for (const char* bad : {"domain=233", "domain=-1", "domain=x", "master=http://127.0.0.1:11311"}) {
        auto refused = parseRos2SourceSpec(std::string(kDepthTopic) + ":" + bad);
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.error().message.find("--source ros2:"), std::string::npos)
            << refused.error().message;
        EXPECT_NE(refused.error().message.find(std::string(bad).substr(0, 6)), std::string::npos)
            << refused.error().message;
    }
    EXPECT_FALSE(parseRosSourceSpec(std::string(kDepthTopic) + ":domain=3")) << "domain= is ROS 2's";
}

TEST(Ros2SourceSpec, ADomainIdFromTheEnvironmentThatIsNoDomainIsAnErrorAtOpen) {
    ASSERT_EQ(setenv("ROS_DOMAIN_ID", "300", 1), 0);
    auto device = openSourceSpec(std::string("ros2:") + kDepthTopic);
    unsetenv("ROS_DOMAIN_ID");
    ASSERT_FALSE(device);
    EXPECT_NE(device.error().message.find("ROS_DOMAIN_ID=300"), std::string::npos) << device.error().message;
}

class Ros2Live : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_EQ(setenv("CYCLONEDDS_URI", kLoopbackConfig, 1), 0); }
    void TearDown() override { camera_.stop(); }

    void publish(std::vector<std::string> options) {
        std::vector<std::string> argv{DC_DDS_CAMERA, "--domain", std::to_string(domain_), "--loopback", "1"};
        argv.insert(argv.end(), options.begin(), options.end());
        camera_ = test::ChildProcess(argv, dir_.path("camera.log"));
        ASSERT_TRUE(camera_.running());
    }
    std::string cameraLog() const { return test::readText(dir_.path("camera.log")); }
    std::string spec(const std::string& options = "") const {
        return std::string(kDepthTopic) + ":domain=" + std::to_string(domain_) + options;
    }
    std::unique_ptr<Device> openDevice(const std::string& options = "") {
        auto device = openSourceSpec("ros2:" + spec(options));
        EXPECT_TRUE(device) << device.error().message;
        if (!device)
            return nullptr;
        const Status opened = (*device)->open();
        EXPECT_TRUE(opened) << opened.error().message;
        const Status started = opened ? (*device)->start() : opened;
        EXPECT_TRUE(started) << started.error().message;
        return started ? std::move(*device) : nullptr;
    }
    static std::vector<frame::FramePtr> capture(Device& device, std::size_t count,
                                                std::chrono::seconds limit) {
        std::vector<frame::FramePtr> frames;
        const auto deadline = Clock::now() + limit;
        while (frames.size() < count && Clock::now() < deadline)
            if (CaptureResult r = device.capture(100ms); r.kind == CaptureResult::Kind::Frame)
                frames.push_back(std::move(r.frame));
        return frames;
    }

    int domain_ = testDomain();
    test::TempDir dir_;
    test::ChildProcess camera_;
};

// The readers match one after another (/tf_static's history comes last): from the first frame with its
// colour, camera_info's lens and its pose on, every frame is paired with the colour stamped 4 ms after it,
// not a neighbour's, and carries its pose from /tf and /tf_static at its stamp.
TEST_F(Ros2Live, EveryFrameArrivesPairedPixelForPixelWithItsLensAndPoseFromTf) {
    publish({"--color-skew-ms", "4", "--tf-root", "odom"});
    auto device = openDevice(":frame=odom");
    ASSERT_TRUE(device);
    const auto whole = [](const frame::FramePtr& f) {
        return !f->capturedImage.empty() && f->pose &&
               std::abs(f->depthIntrinsics().fx - test::camera::kFx * kWidth / 64.0) < 1e-9;
    };
    std::vector<frame::FramePtr> got;
    const auto deadline = Clock::now() + 30s;
    while (got.size() < 6 && Clock::now() < deadline)
        for (frame::FramePtr& f : capture(*device, 1, 1s))
            if (!got.empty() || whole(f))
                got.push_back(std::move(f));
    ASSERT_EQ(got.size(), 6u) << "the colour, camera_info or /tf readers never caught up\n" << cameraLog();
    std::int64_t previous = -1;
    for (const frame::FramePtr& f : got) {
        const std::optional<std::int64_t> sent = frameIndex(f->timestampNs);
        ASSERT_TRUE(sent) << "stamp " << f->timestampNs << " is not one the camera sent";
        const std::int64_t i = *sent;
        EXPECT_GT(i, previous) << "frames out of order";
        previous = i;
        test::camera::expectDepth(*f, i, kWidth, kHeight, false);
        test::camera::expectColor(*f, i, kWidth, kHeight);
        test::camera::expectIntrinsics(*f, kWidth, kHeight);
        ASSERT_TRUE(f->pose) << "frame " << i << " has no pose";
        // odom -> camera_link (1 m up) then camera_link -> the optical frame (90 degrees about z, sliding 1
        // cm a frame): the camera's transforms.
        const std::array<double, 16> expected{
            0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0.01 * static_cast<double>(i % 50), 0.5, 0.75, 1};
        for (std::size_t k = 0; k < 16; ++k)
            EXPECT_NEAR(f->pose->cameraToWorld[k], expected[k], 1e-9) << "frame " << i << " element " << k;
    }
}

// ROS 2's sensor-data profile publishes best effort: heard as well as the default, reliable one.
TEST_F(Ros2Live, ACameraPublishingWithTheSensorDataProfileIsHeardToo) {
    publish({"--qos", "sensor-data", "--size", "64x48", "--color-size", "64x48"});
    auto device = openDevice(":color=none");
    ASSERT_TRUE(device);
    const std::vector<frame::FramePtr> got = capture(*device, 3, 30s);
    ASSERT_EQ(got.size(), 3u) << cameraLog();
    const std::optional<std::int64_t> sent = frameIndex(got.back()->timestampNs);
    ASSERT_TRUE(sent);
    test::camera::expectDepth(*got.back(), *sent, 64, 48, false);
}

TEST_F(Ros2Live, ACameraThatLeavesShowsDisconnectedAndItsReturnStreamsAgain) {
    publish({"--size", "64x48", "--color-size", "64x48"});
    auto device = openSourceSpec("ros2:" + spec(":color=none:watchdog=60000"));
    ASSERT_TRUE(device) << device.error().message;
    Session session(std::move(*device));
    ASSERT_TRUE(session.start());
    ASSERT_TRUE(session.waitForFrame(30s)) << cameraLog();

    camera_.stop(); // killed: its lease (2 s) runs out
    auto deadline = Clock::now() + 20s;
    while (session.state() != DeviceState::Disconnected && Clock::now() < deadline)
        std::this_thread::sleep_for(50ms);
    ASSERT_EQ(session.state(), DeviceState::Disconnected);

    publish({"--size", "64x48", "--color-size", "64x48"});
    while (session.takeLatest()) // frames from before the camera left
        ;
    ASSERT_TRUE(session.waitForFrame(30s)) << cameraLog();
    EXPECT_EQ(session.state(), DeviceState::Streaming);
    bool sawLeft = false;
    for (const SessionEvent& e : session.drainEvents())
        sawLeft |=
            e.state == DeviceState::Disconnected && e.message.find("left DDS domain") != std::string::npos;
    EXPECT_TRUE(sawLeft);
    session.stop();
}

// A writer of another type on the depth topic never matches our reader: said once, in one line, naming both.
TEST_F(Ros2Live, ADepthTopicOfAnotherTypeIsReportedInOneLine) {
    publish({"--depth-type", "string"});
    auto device = openDevice(":color=none");
    ASSERT_TRUE(device);
    std::vector<std::string> problems;
    const auto deadline = Clock::now() + 20s;
    while (problems.empty() && Clock::now() < deadline)
        if (CaptureResult r = device->capture(100ms); r.kind == CaptureResult::Kind::Error)
            problems.push_back(r.message);
    ASSERT_EQ(problems.size(), 1u) << cameraLog();
    EXPECT_EQ(problems[0],
              std::string("ROS 2 topic ") + kDepthTopic + " carries std_msgs/String, not sensor_msgs/Image");
    for (auto until = Clock::now() + 2s; Clock::now() < until;)
        EXPECT_NE(device->capture(100ms).kind, CaptureResult::Kind::Error) << "said more than once";
}

TEST_F(Ros2Live, DevicesCommandListsTheImageTopicsOnTheDomain) {
    publish({"--size", "64x48", "--color-size", "64x48"});
    const std::string environment =
        "ROS_DOMAIN_ID=" + std::to_string(domain_) + " CYCLONEDDS_URI='" + kLoopbackConfig + "'";
    const std::string openLine =
        std::string("  ") + kDepthTopic + "  open with: depthcloud --source ros2:" + kDepthTopic + "\n";
    test::RunResult listed;
    const auto deadline = Clock::now() + 30s;
    do {
        listed = test::runIn(dir_.path(), environment + " " + DEPTHCLOUD_BINARY + " devices");
        ASSERT_EQ(listed.exitCode, 0) << listed.err;
    } while (listed.out.find(openLine) == std::string::npos && Clock::now() < deadline);
    EXPECT_NE(listed.out.find("ROS 2 domain " + std::to_string(domain_)), std::string::npos) << listed.out;
    EXPECT_NE(listed.out.find(openLine), std::string::npos) << listed.out;
    EXPECT_EQ(listed.out.find("/camera/camera/depth/camera_info"), std::string::npos)
        << "camera_info is no image";
}

} // namespace
} // namespace dc::devices::ros::dds_test
