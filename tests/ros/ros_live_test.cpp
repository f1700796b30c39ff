// The live ros: source against the real thing: Debian's roscore on a free port of 127.0.0.1 and a rospy
// camera (publish_camera.py) whose pixels follow formulas recomputed here from each image's stamp, so
// every frame is checked pixel for pixel. Also the spec grammar, and what bad input does.

#include "devices/frame_age.h"
#include "devices/replay/replay_spec.h"
#include "devices/ros/ros_device.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_node.h"
#include "devices/ros/ros_source_spec.h"
#include "devices/session.h"
#include "devices/source_spec.h"
#include "tests/recording/recording_test_support.h"
#include "tests/ros/camera_checks.h"
#include "tests/ros/ros_processes.h"
#include "tests/ros/shell_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <netinet/in.h>
#include <optional>
#include <span>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <tuple>
#include <unistd.h>

namespace dc::devices::ros {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::readText;
using test::runIn;
using test::RunResult;
namespace fs = std::filesystem;

// publish_camera.py's default sizes; its formulas are camera_pattern.h's.
constexpr int kDepthW = 64, kDepthH = 48, kColorW = 80, kColorH = 60;
constexpr const char* kDepthTopic = "/camera/depth/image_rect_raw";
using test::camera::frameIndex;

// The depthcloud binary, run in `dir` with `environment` (VAR=value ...) before it.
RunResult runDepthcloud(const std::string& dir, const std::string& environment,
                        const std::string& arguments) {
    return runIn(dir, environment + " " + DEPTHCLOUD_BINARY + " " + arguments);
}

std::size_t lines(const std::string& text) {
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// One roscore for the suite: roscpp talks to one master per process, so every test uses this one (the
// reconnect test stops and restarts it on the same port).
class RosLive : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir;
        core_ = new test::RosCore(test::freeLocalPort(), dir_->path());
        test::useLocalRosMaster(core_->uri(), dir_->path());
        ASSERT_TRUE(core_->start()) << "roscore did not come up: " << readText(core_->logFile());
    }
    static void TearDownTestSuite() {
        delete core_;
        delete dir_;
    }
    void TearDown() override { publisher_.stop(); }

    void publish(const std::vector<std::string>& options) {
        std::vector<std::string> argv{"/usr/bin/python3", "tests/ros/publish_camera.py"};
        argv.insert(argv.end(), options.begin(), options.end());
        publisher_ = test::ChildProcess(argv, dir_->path("publisher.log"));
        ASSERT_TRUE(publisher_.running());
    }

    static std::unique_ptr<RosDevice> openDevice(const std::string& spec) {
        auto config = parseRosSourceSpec(spec);
        EXPECT_TRUE(config) << config.error().message;
        if (!config)
            return nullptr;
        auto device = std::make_unique<RosDevice>(*config, makeMasterLink(config->masterUri));
        const Status opened = device->open();
        EXPECT_TRUE(opened) << opened.error().message;
        const Status started = opened ? device->start() : opened;
        EXPECT_TRUE(started) << started.error().message;
        return started ? std::move(device) : nullptr;
    }

    // Captures until `count` frames came or the time is up; everything else that came back is kept too.
    struct Captured {
        std::vector<frame::FramePtr> frames;
        std::vector<CaptureResult> others;
    };
    static Captured capture(Device& device, std::size_t count, std::chrono::seconds limit = 15s) {
        Captured out;
        const auto deadline = Clock::now() + limit;
        while (out.frames.size() < count && Clock::now() < deadline) {
            CaptureResult r = device.capture(100ms);
            if (r.kind == CaptureResult::Kind::Frame)
                out.frames.push_back(std::move(r.frame));
            else if (r.kind != CaptureResult::Kind::Timeout)
                out.others.push_back(std::move(r));
        }
        return out;
    }
    std::string publisherLog() const { return readText(dir_->path("publisher.log")); }

    static void expectDepth(const frame::Frame& f, std::int64_t i, bool meters) {
        test::camera::expectDepth(f, i, kDepthW, kDepthH, meters);
    }
    static void expectColor(const frame::Frame& f, std::int64_t i) {
        test::camera::expectColor(f, i, kColorW, kColorH);
    }
    static void expectIntrinsics(const frame::Frame& f) {
        test::camera::expectIntrinsics(f, kDepthW, kDepthH);
    }
    void expectStream(const std::string& encoding, bool meters, const std::string& transport = "raw") {
        publish({"--encoding", encoding, "--color-skew-ms", "4", "--transport", transport});
        // The colour and camera_info are found beside the depth topic, compressed beside compressed.
        auto device =
            openDevice(transport == "raw" ? kDepthTopic : kDepthTopic + std::string("/compressedDepth"));
        ASSERT_TRUE(device);
        const Captured got = capture(*device, 8);
        ASSERT_EQ(got.frames.size(), 8u) << publisherLog();
        // Until the colour and camera_info subscriptions are connected too, the first depth images can only
        // come alone, and after a second's grace with a guessed lens (a busy machine connects them later);
        // from the first pair with camera_info's lens on, every frame carries its own colour and that lens.
        const auto paired = std::find_if(got.frames.begin(), got.frames.end(), [](const frame::FramePtr& f) {
            return !f->capturedImage.empty() && f->depthIntrinsics().fx == test::camera::kFx;
        });
        ASSERT_GE(std::distance(paired, got.frames.end()), 5)
            << "the colour or camera_info subscription never caught up";
        std::int64_t previous = -1;
        for (const frame::FramePtr& f : std::span(paired, got.frames.end())) {
            const std::optional<std::int64_t> sent = frameIndex(f->timestampNs);
            ASSERT_TRUE(sent) << "stamp " << f->timestampNs << " is not one the publisher sent";
            const std::int64_t i = *sent;
            EXPECT_GT(i, previous) << "frames out of order";
            previous = i;
            expectDepth(*f, i, meters);
            expectColor(*f, i); // the colour stamped 4 ms after this depth image, not a neighbour's
            expectIntrinsics(*f);
        }
    }

    static test::TempDir* dir_;
    static test::RosCore* core_;
    test::ChildProcess publisher_;
};

test::TempDir* RosLive::dir_ = nullptr;
test::RosCore* RosLive::core_ = nullptr;

TEST(RosSourceSpec, FindsColorAndCameraInfoBesideTheDepthTopic) {
    const DerivedTopics rs = deriveTopics("/camera/depth/image_rect_raw");
    EXPECT_EQ(rs.color, "/camera/color/image_raw");
    EXPECT_EQ(rs.info, "/camera/depth/camera_info");
    const DerivedTopics aligned = deriveTopics("/cam1/aligned_depth_to_color/image_raw");
    EXPECT_EQ(aligned.color, "/cam1/color/image_raw");
    EXPECT_EQ(aligned.info, "/cam1/aligned_depth_to_color/camera_info");
    const DerivedTopics compressed = deriveTopics("/camera/depth/image_rect_raw/compressedDepth");
    EXPECT_EQ(compressed.color, "/camera/color/image_raw/compressed");
    EXPECT_EQ(compressed.info, "/camera/depth/camera_info");
    const DerivedTopics plain = deriveTopics("/kinect/image_depth");
    EXPECT_EQ(plain.color, "");
    EXPECT_EQ(plain.info, "/kinect/camera_info");
}

TEST(RosSourceSpec, ParsesTopicsMasterAndTimes) {
    auto c =
        parseRosSourceSpec("/cam/depth/image_raw:color=/rgb/image:info=/cam/info:master=http://127.0.0.1:"
                           "11411:tolerance=5:watchdog=700");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->depthTopic, "/cam/depth/image_raw");
    EXPECT_EQ(c->colorTopic, "/rgb/image");
    EXPECT_EQ(c->infoTopic, "/cam/info");
    EXPECT_EQ(c->masterUri, "http://127.0.0.1:11411");
    EXPECT_EQ(c->pairTolerance, 5ms);
    EXPECT_EQ(c->watchdog, 700ms);
    EXPECT_EQ(c->fixedFrame, "");
    auto posed = parseRosSourceSpec("/camera/depth/image_rect_raw:frame=/odom");
    ASSERT_TRUE(posed) << posed.error().message;
    EXPECT_EQ(posed->fixedFrame, "odom");
    auto depthOnly = parseRosSourceSpec("/camera/depth/image_rect_raw:color=none");
    ASSERT_TRUE(depthOnly);
    EXPECT_EQ(depthOnly->colorTopic, "");
    EXPECT_EQ(depthOnly->infoTopic, "/camera/depth/camera_info");
}

TEST(RosSourceSpec, RefusesMalformedSpecsNamingThePart) {
    const std::pair<const char*, const char*> bad[] = {
        {"ros:", "depth topic"},
        {"ros:/cam/depth image", "/cam/depth image"},
        {"ros:/cam/depth:tolerance=-3", "tolerance=-3"},
        {"ros:/cam/depth:master=ftp://x:1", "master=ftp://x:1"},
        {"ros:/cam/depth:master=http://host", "master=http://host"},
        {"ros:/cam/depth:speed=2", "speed=2"},
    };
    for (const auto& [spec, named] : bad) {
        auto device = openSourceSpec(spec);
        ASSERT_FALSE(device) << spec;
        EXPECT_NE(device.error().message.find(named), std::string::npos) << device.error().message;
        EXPECT_EQ(device.error().message.find('\n'), std::string::npos) << device.error().message;
    }
}

TEST(RosMaster, ParsesHttpHostPortAndRefusesTheRest) {
    auto m = parseMasterUri("http://robot.local:11311/");
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_EQ(m->host, "robot.local");
    EXPECT_EQ(m->port, 11311);
    for (const char* bad : {"robot:11311", "http://robot", "http://:11311", "http://robot:0",
                            "http://robot:70000", "http://robot:11311x", "https://robot:11311"})
        EXPECT_FALSE(parseMasterUri(bad)) << bad;
}

// A listening socket that never answers (the kernel completes the connection from the backlog).
class SilentListener {
public:
    SilentListener() {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof address;
        if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
            ::listen(fd_, 4) == 0 && ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
            port_ = ntohs(address.sin_port);
    }
    ~SilentListener() { ::close(fd_); }
    int fd() const { return fd_; }
    int port() const { return port_; }

private:
    int fd_ = -1;
    int port_ = 0;
};

TEST(RosMaster, SomethingThatListensButIsNoMasterIsRefusedNotWaitedFor) {
    SilentListener silent;
    ASSERT_GT(silent.port(), 0);
    auto uri = parseMasterUri("http://127.0.0.1:" + std::to_string(silent.port()));
    ASSERT_TRUE(uri);
    const Status mute = probeMaster(*uri, 300ms);
    ASSERT_FALSE(mute);
    EXPECT_NE(mute.error().message.find("does not answer"), std::string::npos) << mute.error().message;

    // A web server: it answers, but not as a master.
    SilentListener web;
    auto webUri = parseMasterUri("http://127.0.0.1:" + std::to_string(web.port()));
    ASSERT_TRUE(webUri);
    std::thread server([&] {
        const int client = ::accept(web.fd(), nullptr, nullptr);
        char request[1024];
        (void)::recv(client, request, sizeof request, 0);
        const std::string reply = "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\n\r\n";
        (void)::send(client, reply.data(), reply.size(), MSG_NOSIGNAL);
        ::close(client);
    });
    const Status answered = probeMaster(*webUri, 10'000ms);
    server.join();
    ASSERT_FALSE(answered);
    EXPECT_NE(answered.error().message.find("no ROS master (HTTP/1.1 404 Not Found)"), std::string::npos)
        << answered.error().message;
}

TEST(RosCli, UnreachableMasterExitsOneAndMalformedSpecExitsTwoInOneLine) {
    test::TempDir dir;
    const std::string closed = "http://127.0.0.1:" + std::to_string(test::freeLocalPort());
    const RunResult unreachable = runDepthcloud(
        dir.path(), "",
        "record --seconds 1 --source ros:/camera/depth/image_rect_raw:master=" + closed + " a.dcrec");
    EXPECT_EQ(unreachable.exitCode, 1) << unreachable.err;
    EXPECT_EQ(lines(unreachable.err), 1u) << unreachable.err;
    EXPECT_NE(unreachable.err.find(closed + " is not reachable"), std::string::npos) << unreachable.err;

    const RunResult malformed =
        runDepthcloud(dir.path(), "", "record --seconds 1 --source ros:/camera/depth:tolerance=soon b.dcrec");
    EXPECT_EQ(malformed.exitCode, 2) << malformed.err;
    EXPECT_EQ(lines(malformed.err), 1u) << malformed.err;
    EXPECT_NE(malformed.err.find("tolerance=soon"), std::string::npos) << malformed.err;

    const RunResult listing = runDepthcloud(dir.path(), "ROS_MASTER_URI=" + closed, "devices");
    EXPECT_EQ(listing.exitCode, 0) << listing.err;
    EXPECT_NE(listing.out.find("note: ROS master " + closed + " is not reachable"), std::string::npos)
        << listing.out;
}

TEST_F(RosLive, DevicesCommandListsTheImageTopicsOfTheMaster) {
    publish({});
    const std::string openLine =
        "  /camera/depth/image_rect_raw  open with: depthcloud --source ros:/camera/depth/image_rect_raw\n";
    const std::string colourLine = "  /camera/color/image_raw  open with:";
    // The publisher advertises its topics one after another: a listing between two of them lacks the later.
    const auto bothListed = [&](const std::string& out) {
        return out.find(openLine) != std::string::npos && out.find(colourLine) != std::string::npos;
    };
    RunResult listed;
    const auto deadline = Clock::now() + 15s;
    do {
        listed = runDepthcloud(dir_->path(), "", "devices");
        ASSERT_EQ(listed.exitCode, 0) << listed.err;
    } while (!bothListed(listed.out) && Clock::now() < deadline);
    EXPECT_NE(listed.out.find(openLine), std::string::npos) << listed.out;
    EXPECT_NE(listed.out.find(colourLine), std::string::npos) << listed.out;
    EXPECT_EQ(listed.out.find("/camera/depth/camera_info"), std::string::npos) << "camera_info is no image";
}

TEST_F(RosLive, DepthIn16UC1MillimetresArrivesPixelForPixelWithColorAndIntrinsics) {
    expectStream("16UC1", false);
}

TEST_F(RosLive, DepthIn32FC1MetersArrivesPixelForPixel) {
    expectStream("32FC1", true);
}

// image_transport's compressedDepth and compressed topics (PNG: lossless, so pixel for pixel), decoded on
// arrival, paired and placed as the raw topics are.
TEST_F(RosLive, CompressedDepthAndColourTopicsArrivePixelForPixel) {
    expectStream("16UC1", false, "compressed");
    // Streaming, so every topic is advertised: `devices` lists the compressed ones to open too.
    const RunResult listed = runDepthcloud(dir_->path(), "", "devices");
    ASSERT_EQ(listed.exitCode, 0) << listed.err;
    EXPECT_NE(
        listed.out.find("  /camera/depth/image_rect_raw/compressedDepth  open with: depthcloud --source "
                        "ros:/camera/depth/image_rect_raw/compressedDepth\n"),
        std::string::npos)
        << listed.out;
}

TEST_F(RosLive, ColorBeyondTheToleranceIsNotPaired) {
    publish({"--color-skew-ms", "8"});
    auto device = openDevice(std::string(kDepthTopic) + ":tolerance=3");
    ASSERT_TRUE(device);
    const Captured got = capture(*device, 4);
    ASSERT_EQ(got.frames.size(), 4u) << publisherLog();
    for (const frame::FramePtr& f : got.frames) {
        EXPECT_EQ(f->capturedImage.width, 0) << "paired across an 8 ms gap with a 3 ms tolerance";
        const std::optional<std::int64_t> sent = frameIndex(f->timestampNs);
        ASSERT_TRUE(sent) << "stamp " << f->timestampNs << " is not one the publisher sent";
        expectDepth(*f, *sent, false);
    }
    EXPECT_GT(device->pairer().unpaired(), 0u);
    EXPECT_EQ(device->pairer().paired(), 0u);
}

TEST(RosSourceSpec, UnreachableMasterFailsAtOpenInOneLine) {
    const int closedPort = test::freeLocalPort();
    auto device = openSourceSpec(std::string("ros:/camera/depth/image_rect_raw:master=http://127.0.0.1:") +
                                 std::to_string(closedPort));
    ASSERT_TRUE(device) << device.error().message; // the spec is fine: the failure comes at open
    const auto started = Clock::now();
    const Status opened = (*device)->open();
    ASSERT_FALSE(opened);
    EXPECT_LT(Clock::now() - started, 5s);
    EXPECT_NE(opened.error().message.find("not reachable"), std::string::npos) << opened.error().message;
    EXPECT_EQ(opened.error().message.find('\n'), std::string::npos);
}

TEST_F(RosLive, TopicThatIsNoImageIsRefusedAtOpen) {
    publish({"--depth-type", "string"});
    auto config = parseRosSourceSpec(kDepthTopic);
    ASSERT_TRUE(config);
    RosDevice device(*config, makeMasterLink(config->masterUri));
    // The publisher needs a moment to advertise; until then the topic is unknown, which is allowed.
    Status opened;
    const auto deadline = Clock::now() + 15s;
    while ((opened = device.open()) && Clock::now() < deadline) {
        device.close();
        std::this_thread::sleep_for(100ms);
    }
    ASSERT_FALSE(opened) << "a std_msgs/String depth topic was accepted";
    EXPECT_NE(opened.error().message.find("std_msgs/String"), std::string::npos) << opened.error().message;
}

TEST_F(RosLive, UnknownEncodingIsReportedOnceAndTheStreamShowsStalled) {
    publish({"--encoding", "bogus16"});
    auto device = openDevice(std::string(kDepthTopic) + ":watchdog=500");
    ASSERT_TRUE(device);
    std::vector<frame::FramePtr> frames;
    std::vector<std::string> errors;
    const auto collect = [&](std::chrono::seconds limit) {
        Captured more = capture(*device, 1, limit);
        frames.insert(frames.end(), more.frames.begin(), more.frames.end());
        for (const CaptureResult& r : more.others)
            if (r.kind == CaptureResult::Kind::Error)
                errors.push_back(r.message);
    };
    // A slow publisher may start after the watchdog fired: wait for both, in either order.
    const auto deadline = Clock::now() + 15s;
    while ((errors.empty() || device->state() != DeviceState::Stalled) && Clock::now() < deadline)
        collect(1s);
    collect(2s); // dozens more bogus images: still one report
    EXPECT_TRUE(frames.empty());
    EXPECT_EQ(device->state(), DeviceState::Stalled);
    ASSERT_EQ(errors.size(), 1u) << publisherLog();
    EXPECT_NE(errors[0].find("bogus16"), std::string::npos) << errors[0];
}

TEST_F(RosLive, ClockJumpingBackIsReportedAndFramesGoOn) {
    // The publisher's clock jumps 10 s back once the trigger file exists: after frames were seen here.
    const std::string trigger = dir_->path("jump-now");
    fs::remove(trigger);
    publish({"--jump-back-file", trigger, "--start", "1010"});
    auto device = openDevice(kDepthTopic);
    ASSERT_TRUE(device);
    const Captured before = capture(*device, 2);
    ASSERT_EQ(before.frames.size(), 2u) << publisherLog();
    ASSERT_GE(before.frames.back()->timestampNs, 1010'000'000'000);
    std::ofstream(trigger).put('\n');

    std::vector<std::string> reports;
    std::size_t afterJump = 0;
    const auto deadline = Clock::now() + 15s;
    while (afterJump < 3 && Clock::now() < deadline) {
        const Captured more = capture(*device, 1, 1s);
        for (const frame::FramePtr& f : more.frames)
            afterJump += f->timestampNs < 1010'000'000'000 ? 1 : 0;
        for (const CaptureResult& r : more.others)
            reports.push_back(r.message);
    }
    EXPECT_EQ(afterJump, 3u) << publisherLog();
    ASSERT_EQ(reports.size(), 1u);
    // 10 s back from the next frame's stamp: 10 s less a frame period or two.
    EXPECT_NE(reports[0].find("jumped back 99"), std::string::npos) << reports[0];
}

TEST_F(RosLive, StampsArePublishTimesOnTheRealtimeClockSoTheLatencyIsKnown) {
    publish({"--start", "0"}); // stamped with rospy.Time.now()
    auto device = openDevice(kDepthTopic);
    ASSERT_TRUE(device);
    const Captured got = capture(*device, 3);
    ASSERT_EQ(got.frames.size(), 3u) << publisherLog();
    const std::optional<std::int64_t> now = nowOnFrameClockNs(device->capabilities());
    ASSERT_TRUE(now);
    // On another clock (CLOCK_MONOTONIC counts from boot) the age would be off by decades.
    const double ageMs = frameAgeMs(*got.frames.back(), *now);
    EXPECT_GT(ageMs, 0.0);
    EXPECT_LT(ageMs, 60'000.0);
}

TEST_F(RosLive, PoseComesFromTfAndTfStaticAtTheImageStamp) {
    publish({"--tf-root", "map"});
    auto device = openDevice(std::string(kDepthTopic) + ":frame=map");
    ASSERT_TRUE(device);
    EXPECT_TRUE(device->capabilities().pose);
    // The /tf subscription may connect a little after the images': frames before the first pose are
    // skipped, every one after it must have its pose.
    std::vector<frame::FramePtr> posed;
    const auto deadline = Clock::now() + 15s;
    while (posed.size() < 5 && Clock::now() < deadline)
        for (frame::FramePtr& f : capture(*device, 1, 1s).frames)
            if (f->pose || !posed.empty())
                posed.push_back(std::move(f));
    ASSERT_EQ(posed.size(), 5u) << publisherLog();
    for (const frame::FramePtr& f : posed) {
        const std::optional<std::int64_t> sent = frameIndex(f->timestampNs);
        ASSERT_TRUE(sent) << "stamp " << f->timestampNs << " is not one the publisher sent";
        const std::int64_t i = *sent;
        ASSERT_TRUE(f->pose) << "frame " << i << " has no pose";
        // map -> camera_link (1 m up, /tf_static) then camera_link -> optical frame (90 degrees about z,
        // sliding 1 cm a frame, /tf): publish_camera.py's transforms.
        const std::array<double, 16> expected{
            0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0.01 * static_cast<double>(i % 50), 0.5, 0.75, 1};
        for (std::size_t k = 0; k < 16; ++k)
            EXPECT_NEAR(f->pose->cameraToWorld[k], expected[k], 1e-9) << "frame " << i << " element " << k;
    }
}

TEST_F(RosLive, BagRecordedWithRosbagFromTheLiveTopicsReplaysAsSeenLive) {
    publish({"--color-skew-ms", "4"});
    const std::string bagPath = dir_->path("live.bag");
    test::ChildProcess recorder({"rosbag", "record", "-O", bagPath, "/camera/depth/image_rect_raw",
                                 "/camera/color/image_raw", "/camera/depth/camera_info"},
                                dir_->path("rosbag.log"));
    // rosbag writes to live.bag.active while it records; wait until messages go in before watching live.
    const auto recording = Clock::now() + 15s;
    const auto recorded = [&] {
        std::error_code error;
        const auto size = fs::file_size(bagPath + ".active", error);
        return !error && size > 100'000;
    };
    while (!recorded() && Clock::now() < recording)
        std::this_thread::sleep_for(50ms);
    auto device = openDevice(kDepthTopic);
    ASSERT_TRUE(device);
    // The colour subscription may connect a little after the depth's (a loaded machine): frames before the
    // first colour are depth alone, and skipped; every one after it must have its colour.
    Captured live;
    const auto deadline = Clock::now() + 15s;
    while (live.frames.size() < 8 && Clock::now() < deadline)
        for (frame::FramePtr& f : capture(*device, 1, 1s).frames)
            if (f->capturedImage.bytes || !live.frames.empty())
                live.frames.push_back(std::move(f));
    ASSERT_EQ(live.frames.size(), 8u) << publisherLog();
    device.reset();
    recorder.stop();
    ASSERT_TRUE(fs::exists(bagPath)) << readText(dir_->path("rosbag.log"));

    auto bag = replay::openReplaySpecSource(bagPath);
    ASSERT_TRUE(bag) << bag.error().message;
    std::size_t compared = 0;
    for (const frame::FramePtr& seen : live.frames) {
        const std::size_t i = (*bag)->indexAtTime(seen->timestampNs);
        ASSERT_EQ((*bag)->timestampNs(i), seen->timestampNs) << "a frame seen live is missing from the bag";
        auto replayed = (*bag)->frame(i);
        ASSERT_TRUE(replayed) << replayed.error().message;
        ASSERT_TRUE(seen->capturedImage.bytes) << "a frame seen live after the first colour has none";
        ASSERT_TRUE(replayed->capturedImage.bytes) << "the bag's frame has no colour";
        EXPECT_EQ(replayed->sceneDepth->depthMeters.pixels, seen->sceneDepth->depthMeters.pixels);
        EXPECT_EQ(*replayed->capturedImage.bytes, *seen->capturedImage.bytes);
        EXPECT_EQ(replayed->capturedImage.format, seen->capturedImage.format);
        const frame::Intrinsics a = replayed->cameraIntrinsics, b = seen->cameraIntrinsics;
        EXPECT_EQ(std::tie(a.fx, a.fy, a.cx, a.cy, a.width, a.height),
                  std::tie(b.fx, b.fy, b.cx, b.cy, b.width, b.height));
        ++compared;
    }
    EXPECT_EQ(compared, live.frames.size());
}

TEST_F(RosLive, PublisherThatStopsShowsStalledAndItsReturnStreamsAgain) {
    publish({});
    auto device = openDevice(std::string(kDepthTopic) + ":watchdog=500");
    ASSERT_TRUE(device);
    ASSERT_EQ(capture(*device, 1).frames.size(), 1u) << publisherLog();

    publisher_.stop();
    const auto deadline = Clock::now() + 10s;
    while (device->state() != DeviceState::Stalled && Clock::now() < deadline)
        (void)capture(*device, 1, 1s);
    ASSERT_EQ(device->state(), DeviceState::Stalled);

    publish({}); // the master tells the subscriber about the new publisher
    const Captured again = capture(*device, 2);
    ASSERT_EQ(again.frames.size(), 2u) << publisherLog();
    EXPECT_EQ(device->state(), DeviceState::Streaming);
    const std::optional<std::int64_t> sent = frameIndex(again.frames.back()->timestampNs);
    ASSERT_TRUE(sent) << "stamp " << again.frames.back()->timestampNs << " is not one the publisher sent";
    expectDepth(*again.frames.back(), *sent, false);
}

TEST_F(RosLive, MasterThatGoesAwayShowsDisconnectedAndStreamingResumesWhenItIsBack) {
    publish({});
    auto device = openSourceSpec(std::string("ros:") + kDepthTopic + ":color=none");
    ASSERT_TRUE(device);
    Session session(std::move(*device));
    ASSERT_TRUE(session.start());
    ASSERT_TRUE(session.waitForFrame(15s)) << publisherLog();

    publisher_.stop();
    core_->stop();
    auto deadline = Clock::now() + 10s;
    while (session.state() != DeviceState::Disconnected && Clock::now() < deadline)
        std::this_thread::sleep_for(50ms);
    ASSERT_EQ(session.state(), DeviceState::Disconnected);

    ASSERT_TRUE(core_->start());
    publish({});
    while (session.takeLatest()) // frames from before the master went away
        ;
    ASSERT_TRUE(session.waitForFrame(20s)) << publisherLog();
    EXPECT_EQ(session.state(), DeviceState::Streaming);
    bool sawDisconnected = false;
    for (const SessionEvent& e : session.drainEvents())
        sawDisconnected |=
            e.state == DeviceState::Disconnected && e.message.find("not reachable") != std::string::npos;
    EXPECT_TRUE(sawDisconnected);
    session.stop();
}

} // namespace
} // namespace dc::devices::ros
