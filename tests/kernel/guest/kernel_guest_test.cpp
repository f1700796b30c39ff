// Runs inside the kernel-tier VM (tests/kernel/vmkit/init.sh): our V4L2, libusb and device code against a
// real kernel's uvcvideo, UVC gadget, v4l2loopback and vivid. The scenario passes what it set up through
// the environment; a missing variable is a failure, never a skip.

#include "base/files.h"
#include "base/log.h"
#include "devices/frame_age.h"
#include "devices/session.h"
#include "devices/source_spec.h"
#include "devices/uvc/live_device_watcher.h"
#include "devices/uvc/live_devices.h"
#include "devices/uvc/live_source_spec.h"
#include "devices/uvc/usb/hotplug_monitor.h"
#include "devices/uvc/usb/usb_enumeration.h"
#include "devices/uvc/uvc_device.h"
#include "devices/uvc/v4l2/control_preset.h"
#include "devices/uvc/v4l2/controls.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "engine/timing_model.h"
#include "frame/calibration.h"
#include "processing/registration.h"
#include "tests/kernel/vmkit/src/test_pattern.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <thread>

namespace dc::devices {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr float kD435Scale = 0.001f; // the known-camera table's value for 8086:0b07

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

// The next capture that is a frame or an error: a capture that took a buffer but completed no frame (a
// depth frame whose colour is still on its way) comes back as a timeout, and is tried again.
CaptureResult nextCapture(Device& device) {
    const auto end = Clock::now() + 20s;
    CaptureResult r;
    while (r.kind == CaptureResult::Kind::Timeout && Clock::now() < end)
        r = device.capture(5000ms);
    return r;
}

// Checks a depth map against the feeder's pattern under a brightness offset (test_pattern.h dc_lit_pattern):
// every pixel must be exactly raw * scale of the raw value the feeder sent for that frame. Returns the
// frame number, or what differs.
Expected<long> patternFrame(const frame::Plane<float>& meters, float scale, int brightnessOffset = 0) {
    const auto raw = [&](int x, int y) { return std::lround(meters.at(x, y) / scale); };
    if (meters.width != kWidth || meters.height != kHeight)
        return Error{"size " + std::to_string(meters.width) + "x" + std::to_string(meters.height)};
    const auto frame = static_cast<unsigned>(raw(0, 0) | (raw(1, 0) << 16));
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const std::uint16_t expected =
                dc_lit_pattern(static_cast<unsigned>(x), static_cast<unsigned>(y), frame, brightnessOffset);
            if (meters.at(x, y) != static_cast<float>(expected) * scale)
                return Error{"pixel (" + std::to_string(x) + "," + std::to_string(y) + ") of frame " +
                             std::to_string(frame) + " is " + std::to_string(meters.at(x, y)) +
                             " m, the feeder sent " + std::to_string(expected)};
        }
    return static_cast<long>(frame);
}

// Captures `count` frames from a device and checks each against the pattern; frame numbers must rise.
void expectPatternFrames(Device& device, int count, float scale) {
    long last = -1;
    for (int got = 0; got < count;) {
        const CaptureResult r = nextCapture(device);
        ASSERT_TRUE(r.kind == CaptureResult::Kind::Frame || r.kind == CaptureResult::Kind::Error)
            << "no frame (" << static_cast<int>(r.kind) << "): " << r.message;
        if (r.kind != CaptureResult::Kind::Frame) {
            std::printf("capture error (frame dropped): %s\n", r.message.c_str());
            continue;
        }
        const Expected<long> frame = patternFrame(r.frame->sceneDepth->depthMeters, scale);
        ASSERT_TRUE(frame) << frame.error().message;
        EXPECT_GT(*frame, last) << "frames arrive in order";
        std::printf("frame %ld: pattern exact, age at capture %.1f ms\n", *frame, frameAgeMs(*r.frame));
        last = *frame;
        ++got;
    }
}

template <class Predicate> bool waitFor(Predicate done, std::chrono::seconds limit) {
    const auto end = Clock::now() + limit;
    while (!done()) {
        if (Clock::now() > end)
            return false;
        std::this_thread::sleep_for(50ms);
    }
    return true;
}

bool writeSysfs(const std::string& path, const std::string& value) {
    std::ofstream out(path);
    out << value << "\n";
    out.flush();
    return static_cast<bool>(out);
}

// ---- the UVC gadget camera (uvcvideo on dummy_hcd) -------------------------------------------------

TEST(Uvc, LibusbFindsTheCameraWithItsStrings) {
    ASSERT_FALSE(env("VIDEO").empty());
    auto devices = usb::enumerateUsbDevices();
    ASSERT_TRUE(devices) << devices.error().message;
    const auto camera = std::find_if(devices->begin(), devices->end(),
                                     [](const usb::UsbDeviceInfo& d) { return d.id() == "8086:0b07"; });
    ASSERT_NE(camera, devices->end());
    EXPECT_EQ(camera->manufacturer, "Fake Depth Inc");
    EXPECT_EQ(camera->product, "Virtual Z16 Depth Camera");
    EXPECT_EQ(camera->serial, "VDC0001");
    EXPECT_TRUE(camera->hasVideoInterface);
    EXPECT_EQ(camera->sysfsName(), "1-1");
    const auto nodes = usb::Sysfs().videoNodesOf(camera->sysfsName());
    EXPECT_NE(std::find(nodes.begin(), nodes.end(), env("VIDEO")), nodes.end());
}

TEST(Uvc, TheListingNamesTheDepthNodeAndItsZ16Mode) {
    const LiveDeviceListing listing = listLiveDevices();
    const auto camera =
        std::find_if(listing.devices.begin(), listing.devices.end(),
                     [](const LiveDeviceInfo& d) { return d.usb && d.usb->id() == "8086:0b07"; });
    ASSERT_NE(camera, listing.devices.end());
    EXPECT_EQ(camera->depthNode, env("VIDEO"));
    EXPECT_EQ(camera->knownModel, "Intel RealSense D435");
    EXPECT_EQ(camera->sourceSpec, "usb:8086:0b07:VDC0001");
    bool z16 = false;
    for (const VideoNodeInfo& node : camera->nodes)
        for (const NodeMode& m : node.modes)
            z16 |= node.path == camera->depthNode && m.fourcc == "Z16 " && m.width == kWidth &&
                   m.height == kHeight;
    EXPECT_TRUE(z16);
    for (const std::string& p : listing.problems)
        std::printf("listing note: %s\n", p.c_str());
}

TEST(Uvc, V4l2NodeStreamsTheFeedersPatternPixelForPixel) {
    v4l2::V4l2Node node;
    ASSERT_EQ(node.open(env("VIDEO")), 0);
    EXPECT_EQ(node.capability().driver, "uvcvideo");
    v4l2::V4l2Format f{V4L2_PIX_FMT_Z16, kWidth, kHeight, 0, 0};
    ASSERT_EQ(node.setFormat(f), 0);
    ASSERT_EQ(f.fourcc, V4L2_PIX_FMT_Z16);
    ASSERT_EQ(node.allocateBuffers(), static_cast<int>(v4l2::V4l2Node::kBufferCount));
    ASSERT_EQ(node.streamOn(), 0);
    long last = -1;
    std::vector<v4l2::NodeReadiness> ready;
    v4l2::V4l2Node* nodes[] = {&node};
    for (int got = 0; got < 10;) {
        ASSERT_GT(v4l2::waitForNodes(v4l2::systemSyscalls(), nodes, nullptr, 5000, ready), 0)
            << "no frame in 5 s";
        const v4l2::DequeueResult d = node.dequeue();
        if (d.kind == v4l2::DequeueResult::Kind::NotReady)
            continue;
        ASSERT_EQ(d.kind, v4l2::DequeueResult::Kind::Buffer) << d.message;
        frame::Plane<float> units;
        v4l2::depthToMeters(d.buffer.bytes, kWidth, kHeight, f.bytesPerLine, 1.0f, units);
        const Expected<long> frame = patternFrame(units, 1.0f);
        ASSERT_TRUE(frame) << frame.error().message;
        EXPECT_GT(*frame, last);
        EXPECT_TRUE(d.buffer.monotonicTimestamp);
        last = *frame;
        ASSERT_EQ(node.requeue(d.buffer.index), 0);
        ++got;
    }
    node.close();
}

TEST(Uvc, DepthInMetersEqualsWhatTheFeederSent) {
    auto device = openLiveSourceSpec("usb:8086:0b07");
    ASSERT_TRUE(device) << device.error().message;
    ASSERT_TRUE((*device)->open());
    ASSERT_TRUE((*device)->start());
    EXPECT_TRUE((*device)->capabilities().approximateIntrinsics);
    expectPatternFrames(**device, 10, kD435Scale);
    (*device)->close();
}

// ---- two sensors: the gadget's colour function beside its depth function -------------------------

constexpr int kColourWidth = 320; // the colour function's YUYV size (init.sh)
constexpr int kColourHeight = 240;

// The calibration the test gives the camera, in plain numbers: a 640x480 depth sensor, a 320x240 colour
// sensor with a narrower view, turned 0.02 rad about y and 5 cm to the side, both without lens distortion.
constexpr double kFxD = 500.0, kFyD = 500.0, kCxD = 319.5, kCyD = 239.5;
constexpr double kFxC = 280.0, kFyC = 280.0, kCxC = 160.25, kCyC = 118.75;
constexpr double kAngle = 0.02;
constexpr std::array<double, 3> kT{-0.05, 0.01, 0.002};

frame::RigCalibration testRig() {
    frame::RigCalibration rig;
    rig.depth.intrinsics = {kFxD, kFyD, kCxD, kCyD, kWidth, kHeight};
    rig.colour.intrinsics = {kFxC, kFyC, kCxC, kCyC, kColourWidth, kColourHeight};
    const double c = std::cos(kAngle), s = std::sin(kAngle);
    rig.depthToColour.rotation = {c, 0, s, 0, 1, 0, -s, 0, c};
    rig.depthToColour.translationMeters = kT;
    return rig;
}

// Where depth pixel (x, y) at z meters lands in the colour image: unproject, rotate about y, move, project.
std::array<double, 2> expectedColourPixel(int x, int y, double z) {
    const double px = (x - kCxD) / kFxD * z, py = (y - kCyD) / kFyD * z;
    const double c = std::cos(kAngle), s = std::sin(kAngle);
    const double qx = c * px + s * z + kT[0], qy = py + kT[1], qz = -s * px + c * z + kT[2];
    return {kFxC * qx / qz + kCxC, kFyC * qy / qz + kCyC};
}

// A projection this close to the border between two pixels could be rounded either way.
bool nearPixelBorder(double v) {
    return std::abs(v - std::floor(v) - 0.5) < 0.05;
}

// Whether the colour pixel of a projection is certain: inside the image, not on a pixel border, and away
// from where the first row's frame number lands (a sample far nearer than the rest, hiding what is behind).
bool predictable(const std::array<double, 2>& p, const frame::Plane<float>& depth) {
    const auto odd = expectedColourPixel(0, 0, depth.at(0, 0));
    return p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= kColourWidth - 1.0 && p[1] <= kColourHeight - 1.0 &&
           !nearPixelBorder(p[0]) && !nearPixelBorder(p[1]) &&
           std::hypot(p[0] - odd[0], p[1] - odd[1]) >= 3.0;
}

// Checks one rig frame: the colour image is the feeder's pattern, and the registration puts sampled depth
// pixels on the colour pixel the calibration predicts, whose pattern spells that very pixel. Returns the
// number of depth pixels checked.
int expectRegisteredAsPredicted(const frame::Frame& f) {
    const frame::Plane<float>& depth = f.sceneDepth->depthMeters;
    const auto* bytes = f.capturedImage.bytes->data();
    const auto spells = [&](int x, int y) {
        unsigned px = 0, py = 0;
        dc_colour_pattern_at(bytes, kColourWidth, static_cast<unsigned>(x), static_cast<unsigned>(y), &px,
                             &py);
        return static_cast<int>(px) == x && static_cast<int>(py) == y;
    };
    int wrong = 0;
    for (int y = 0; y < kColourHeight; ++y)
        for (int x = 0; x < kColourWidth; ++x)
            wrong += !spells(x, y);
    EXPECT_EQ(wrong, 0) << "colour pixels that are not the feeder's pattern";
    const processing::Registration reg =
        processing::registerDepth(depth, *f.rig, kColourWidth, kColourHeight);
    int checked = 0, misplaced = 0;
    for (int y = 8; y < kHeight; y += 12)
        for (int x = 5; x < kWidth; x += 12) {
            const auto [u, v] = expectedColourPixel(x, y, depth.at(x, y));
            if (!predictable({u, v}, depth))
                continue;
            const auto cu = static_cast<int>(std::lround(u)), cv = static_cast<int>(std::lround(v));
            const std::int32_t got = reg.colourPixel[static_cast<std::size_t>(y) * kWidth + x];
            if (got != cv * kColourWidth + cu && misplaced++ == 0)
                ADD_FAILURE() << "depth (" << x << "," << y << ") at " << depth.at(x, y)
                              << " m should land on colour (" << cu << "," << cv << "), registered to "
                              << (got < 0 ? std::string("nothing")
                                          : std::to_string(got % kColourWidth) + "," +
                                                std::to_string(got / kColourWidth));
            ++checked;
        }
    EXPECT_EQ(misplaced, 0) << "of " << checked << " depth pixels";
    return checked;
}

// The colour the points get (the cloud's, fog's and upsampling's source) is the predicted pixel's.
void expectPointColoursFromThePredictedPixels(const frame::Frame& f) {
    const frame::Plane<float>& depth = f.sceneDepth->depthMeters;
    processing::CameraColourTable table;
    const processing::PointColours colours = processing::framePointColours(f, depth, table);
    ASSERT_TRUE(colours.colours && colours.seen) << "colours registered from a second sensor";
    ASSERT_TRUE(table.use(f.capturedImage));
    int compared = 0;
    for (int y = 20; y < kHeight; y += 40)
        for (int x = 20; x < kWidth; x += 40) {
            const auto [u, v] = expectedColourPixel(x, y, depth.at(x, y));
            if (!predictable({u, v}, depth))
                continue;
            const std::size_t i = static_cast<std::size_t>(y) * kWidth + x;
            const std::uint32_t expected =
                table.rgba(static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v)));
            EXPECT_EQ(processing::packRgba(&colours.colours->pixels[3 * i]), expected) << x << "," << y;
            ++compared;
        }
    EXPECT_GT(compared, 50);
}

TEST(Uvc, DepthAndColourArrivePairedAndRegisteredWithTheCalibrationGiven) {
    ASSERT_FALSE(env("COLOUR_VIDEO").empty());
    const std::string path = env("TMPDIR") + "/rig.yaml";
    const frame::RigCalibration rig = testRig();
    const auto text = frame::writeCalibration({rig.colour.intrinsics, "", rig, "", ""},
                                              frame::CalibrationFormat::OpenCvStereoYaml);
    ASSERT_TRUE(text) << text.error().message;
    std::ofstream(path) << *text;
    // Checking a frame takes seconds under TCG: longer than the default watchdog, which would call the
    // camera stalled between two captures.
    auto device = openLiveSourceSpec("usb:8086:0b07:watchdog=60000:calib=" + path);
    ASSERT_TRUE(device) << device.error().message;
    auto& uvc = dynamic_cast<UvcDevice&>(**device);
    ASSERT_TRUE(uvc.open());
    ASSERT_TRUE(uvc.start());
    EXPECT_EQ(uvc.colorNodePath(), env("COLOUR_VIDEO")) << "the camera's own colour node";
    EXPECT_FALSE(uvc.capabilities().unregisteredColour);
    int rigFrames = 0, checked = 0;
    for (int i = 0; i < 60 && rigFrames < 5; ++i) {
        const CaptureResult r = nextCapture(uvc);
        ASSERT_TRUE(r.kind == CaptureResult::Kind::Frame || r.kind == CaptureResult::Kind::Error)
            << "no frame (" << static_cast<int>(r.kind) << "): " << r.message;
        if (r.kind != CaptureResult::Kind::Frame || r.frame->capturedImage.empty())
            continue; // an error or a depth frame whose colour came too late: counted by the pairer
        const frame::Frame& f = *r.frame;
        ASSERT_TRUE(f.rig) << "a paired frame carries the calibration";
        EXPECT_NEAR(f.rig->depthToColour.translationMeters[0], kT[0], 1e-9);
        EXPECT_EQ(f.capturedImage.format, frame::PixelFormat::Yuyv);
        ASSERT_EQ(f.capturedImage.width, kColourWidth);
        ASSERT_EQ(f.capturedImage.height, kColourHeight);
        EXPECT_EQ(f.cameraIntrinsics, rig.colour.intrinsics)
            << "a rig frame's image intrinsics: the colour sensor's";
        EXPECT_EQ(f.depthIntrinsics(), rig.depth.intrinsics);
        const Expected<long> number = patternFrame(f.sceneDepth->depthMeters, kD435Scale);
        ASSERT_TRUE(number) << number.error().message;
        checked += expectRegisteredAsPredicted(f);
        if (rigFrames == 0)
            expectPointColoursFromThePredictedPixels(f);
        ++rigFrames;
        std::printf("frame %ld: depth and colour paired, registered as the calibration predicts\n", *number);
    }
    EXPECT_EQ(rigFrames, 5);
    EXPECT_GT(checked, 5 * 300) << "depth pixels compared with the prediction";
    std::printf("METRIC uvcRigPaired=%llu unpaired=%llu (pairer, TCG guest)\n",
                static_cast<unsigned long long>(uvc.pairer().paired()),
                static_cast<unsigned long long>(uvc.pairer().unpaired()));
    uvc.close();
}

TEST(Uvc, AColourNodeWithoutTwoSensorCalibrationIsSaidToBeUnregistered) {
    auto device = openLiveSourceSpec("usb:8086:0b07");
    ASSERT_TRUE(device) << device.error().message;
    EXPECT_TRUE((*device)->capabilities().unregisteredColour);
    ASSERT_TRUE((*device)->open());
    ASSERT_TRUE((*device)->start());
    CaptureResult r;
    for (int i = 0; i < 20 && !(r.frame && !r.frame->capturedImage.empty()); ++i)
        r = nextCapture(**device);
    ASSERT_TRUE(r.frame && !r.frame->capturedImage.empty()) << r.message;
    EXPECT_FALSE(r.frame->rig) << "no calibration relates the sensors";
    (*device)->close();
}

bool sawHotplug(const std::vector<usb::HotplugEvent>& events, usb::HotplugEvent::Kind kind) {
    return std::any_of(events.begin(), events.end(), [&](const usb::HotplugEvent& e) {
        return e.kind == kind && e.device.id() == "8086:0b07";
    });
}

// Whether the device picker's camera list, as the watcher last published it, holds the camera.
bool pickerShowsCamera(LiveDeviceWatcher& watcher, bool& shown) {
    if (auto listing = watcher.takeUpdate())
        shown = std::any_of(listing->devices.begin(), listing->devices.end(), [](const LiveDeviceInfo& d) {
            return d.sourceSpec.starts_with("usb:8086:0b07");
        });
    return shown;
}

TEST(Uvc, UnplugDisconnectsAndReplugResumesWithoutARestart) {
    ASSERT_FALSE(env("UDC_FILE").empty());
    usb::HotplugMonitor hotplug;
    ASSERT_TRUE(hotplug.start());
    LiveDeviceWatcher picker(std::chrono::hours(1)); // polling only as a fallback, which must not happen here
    ASSERT_TRUE(picker.watchingEvents()) << "udev's monitor drives the device picker";
    bool pickerShows = false;
    EXPECT_TRUE(waitFor([&] { return pickerShowsCamera(picker, pickerShows); }, 20s)) << "listed at start";
    auto device = openLiveSourceSpec("usb:8086:0b07");
    ASSERT_TRUE(device);
    Session session(std::move(*device));
    ASSERT_TRUE(session.start());
    ASSERT_TRUE(session.waitForFrame(10s)) << "streaming before the unplug";
    std::vector<usb::HotplugEvent> events;
    const auto collect = [&] {
        for (auto& e : hotplug.drain())
            events.push_back(std::move(e));
    };
    ASSERT_TRUE(writeSysfs(env("UDC_FILE"), "")) << "unbinding the gadget from its UDC";
    EXPECT_TRUE(waitFor([&] { return session.state() == DeviceState::Disconnected; }, 20s));
    EXPECT_TRUE(waitFor(
        [&] {
            collect();
            return sawHotplug(events, usb::HotplugEvent::Kind::Left);
        },
        20s))
        << "libusb reported the unplug";
    EXPECT_TRUE(waitFor([&] { return !pickerShowsCamera(picker, pickerShows); }, 20s))
        << "the device picker dropped the camera";
    (void)session.takeLatest(); // the view keeps its last frame; nothing new arrives now
    ASSERT_TRUE(writeSysfs(env("UDC_FILE"), env("UDC_NAME"))) << "binding it again";
    EXPECT_TRUE(waitFor(
        [&] {
            collect();
            return sawHotplug(events, usb::HotplugEvent::Kind::Arrived);
        },
        30s))
        << "libusb reported the replug";
    EXPECT_TRUE(waitFor([&] { return pickerShowsCamera(picker, pickerShows); }, 30s))
        << "the device picker lists the camera again";
    ASSERT_TRUE(waitFor([&] { return session.state() == DeviceState::Streaming; }, 60s)) << "reconnected";
    const auto frame = session.waitForFrame(20s);
    ASSERT_TRUE(frame.has_value()) << "frames flow again in the same process";
    const Expected<long> number = patternFrame((*frame)->sceneDepth->depthMeters, kD435Scale);
    EXPECT_TRUE(number) << number.error().message;
    std::vector<DeviceState> states;
    for (const SessionEvent& e : session.drainEvents())
        if (e.kind == SessionEvent::Kind::StateChanged) {
            states.push_back(e.state);
            std::printf("session: %s %s\n", toString(e.state), e.message.c_str());
        }
    EXPECT_NE(std::find(states.begin(), states.end(), DeviceState::Disconnected), states.end());
    EXPECT_EQ(states.back(), DeviceState::Streaming);
    for (int i = 0; i < 20; ++i)
        (void)session.waitForFrame(2s);
    std::printf("METRIC uvcLatencyMs=%.2f (median DQBUF timestamp -> consumer, TCG guest)\n",
                session.stats().latencyMs);
}

TEST(Uvc, AStalledFeederShowsStalledThenStreamsAgain) {
    const pid_t feeder = static_cast<pid_t>(std::atoi(env("FEEDER_PID").c_str()));
    ASSERT_GT(feeder, 0);
    auto device = openLiveSourceSpec("usb:8086:0b07:watchdog=1500");
    ASSERT_TRUE(device);
    Session session(std::move(*device));
    ASSERT_TRUE(session.start());
    ASSERT_TRUE(session.waitForFrame(10s));
    ASSERT_EQ(::kill(feeder, SIGUSR1), 0) << "pausing the feeder";
    EXPECT_TRUE(waitFor([&] { return session.state() == DeviceState::Stalled; }, 20s));
    bool watchdogMessage = false;
    for (const SessionEvent& e : session.drainEvents())
        watchdogMessage |= e.state == DeviceState::Stalled && e.message.find("watchdog") != std::string::npos;
    EXPECT_TRUE(watchdogMessage);
    ASSERT_EQ(::kill(feeder, SIGUSR2), 0) << "resuming it";
    EXPECT_TRUE(waitFor([&] { return session.state() == DeviceState::Streaming; }, 20s));
    EXPECT_TRUE(session.waitForFrame(10s));
}

// The feeder's number of a frame, from the pattern's first two pixels.
long feederNumber(const frame::Frame& f) {
    const auto& m = f.sceneDepth->depthMeters;
    return std::lround(m.at(0, 0) / kD435Scale) | (std::lround(m.at(1, 0) / kD435Scale) << 16);
}

// While it lives, the depth feeder sends every FEEDER_SKIP_EVERY-th frame short (uvcfeeder -k): the host's
// uvcvideo drops it as corrupt and its sequence counter counts it.
struct FeederSkipping {
    explicit FeederSkipping(pid_t feeder) : pid(feeder) { ok = ::kill(pid, SIGRTMIN) == 0; }
    ~FeederSkipping() { ::kill(pid, SIGRTMIN + 1); }
    pid_t pid;
    bool ok = false;
};

struct Tapped {
    long number = 0; // the feeder's
    frame::FrameTiming timing;
    std::int64_t timestampNs = 0;
};

// The frames the feeder skipped are exactly the gaps in the driver's sequence of the frames that arrived,
// and exactly what the Timing model counts as lost in the camera/USB; the driver stamps the start of
// exposure on CLOCK_MONOTONIC, and the stamps rise.
TEST(Uvc, FramesTheFeederSkipsAreTheTimingModelsCameraLossesExactly) {
    const pid_t feeder = static_cast<pid_t>(std::atoi(env("FEEDER_PID").c_str()));
    const long every = std::atol(env("FEEDER_SKIP_EVERY").c_str());
    ASSERT_GT(feeder, 0);
    ASSERT_GT(every, 1);
    auto device = openLiveSourceSpec("usb:8086:0b07:color=none");
    ASSERT_TRUE(device) << device.error().message;
    // The depth node's metadata node streams beside it, in D4XX where uvcvideo offers it (it does not for
    // the gadget, though it borrows a D435's ids), and no frame is lost for it. The gadget's 2-byte payload
    // headers leave its buffers empty.
    const auto* uvc = dynamic_cast<const UvcDevice*>(device->get());
    ASSERT_NE(uvc, nullptr);
    std::mutex warningsMutex;
    std::vector<std::string> metadataWarnings;
    const std::uint64_t sink = setLogSink([&](LogLevel level, const std::string& message) {
        std::lock_guard lock(warningsMutex);
        if (level >= LogLevel::Warning && message.find("metadata") != std::string::npos)
            metadataWarnings.push_back(message);
    });
    {
        std::lock_guard lock(warningsMutex);
        metadataWarnings.clear(); // what was logged before this camera opened
    }
    Session session(std::move(*device));
    std::mutex tappedMutex;
    std::vector<Tapped> tapped;
    session.setFrameTap([&](const frame::FramePtr& f) {
        std::lock_guard lock(tappedMutex);
        tapped.push_back({feederNumber(*f), f->timing, f->timestampNs});
    });
    ASSERT_TRUE(session.start());
    ASSERT_TRUE(session.waitForFrame(10s));
    ASSERT_FALSE(uvc->metadataNodePath().empty());
    v4l2::V4l2Node metadataNode(v4l2::systemSyscalls(), v4l2::BufferKind::Metadata);
    ASSERT_EQ(metadataNode.open(uvc->metadataNodePath()), 0);
    const std::vector<std::uint32_t> offered = metadataNode.formats();
    const bool d4xx = std::find(offered.begin(), offered.end(), V4L2_META_FMT_D4XX) != offered.end();
    EXPECT_EQ(uvc->metadataFormat(), d4xx ? V4L2_META_FMT_D4XX : V4L2_META_FMT_UVC);
    std::printf("metadata node %s, '%s' of %zu offered\n", uvc->metadataNodePath().c_str(),
                v4l2::fourccToString(uvc->metadataFormat()).c_str(), offered.size());
    const auto count = [&] {
        std::lock_guard lock(tappedMutex);
        return static_cast<long>(tapped.size());
    };
    {
        FeederSkipping skipping(feeder);
        ASSERT_TRUE(skipping.ok) << "signalling the feeder";
        const long before = count();
        ASSERT_TRUE(waitFor([&] { return count() >= before + 6 * every; }, 60s)) << count() << " frames";
    }
    session.stop();
    removeLogSink(sink);
    for (const std::string& warning : metadataWarnings)
        ADD_FAILURE() << warning;
    engine::TimingModel model;
    for (const FrameRecord& r : session.drainFrameRecords())
        model.add(r);
    const engine::TimingSummary t = model.summary();

    std::lock_guard lock(tappedMutex);
    std::vector<long> missing;
    for (std::size_t i = 1; i < tapped.size(); ++i) {
        const Tapped &a = tapped[i - 1], &b = tapped[i];
        ASSERT_TRUE(a.timing.depth.driverSequence && b.timing.depth.driverSequence);
        EXPECT_EQ(static_cast<long>(*b.timing.depth.driverSequence - *a.timing.depth.driverSequence),
                  b.number - a.number)
            << "the driver counted every frame the feeder sent, frame " << b.number;
        EXPECT_GT(b.timestampNs, a.timestampNs) << "timestamps rise, frame " << b.number;
        EXPECT_EQ(b.timing.depth.source, frame::TimestampSource::StartOfExposure);
        EXPECT_TRUE(b.timing.depth.monotonic);
        for (long n = a.number + 1; n < b.number; ++n)
            missing.push_back(n);
    }
    std::printf("feeder frames %ld..%ld arrived but for", tapped.front().number, tapped.back().number);
    for (const long n : missing)
        std::printf(" %ld", n);
    std::printf("; driver sequence %u..%u\n", *tapped.front().timing.depth.driverSequence,
                *tapped.back().timing.depth.driverSequence);
    ASSERT_GE(missing.size(), 4u) << "the feeder skipped frames while asked to";
    for (const long n : missing)
        EXPECT_EQ(n % every, 0) << "frame " << n << " was lost though the feeder sent it whole";
    // Skipping stayed on from the first frame skipped: every multiple after it up to the last arrived frame
    // (the last arrivals may come after skipping ended) was lost.
    for (long n = missing.front(); n <= missing.back(); n += every)
        EXPECT_NE(std::find(missing.begin(), missing.end(), n), missing.end()) << "frame " << n << " arrived";
    EXPECT_EQ(t.drops.cameraUsb, missing.size()) << "the Timing model counts exactly those";
    EXPECT_EQ(t.delivered, tapped.size());
    EXPECT_EQ(t.depth.source, frame::TimestampSource::StartOfExposure);
    EXPECT_TRUE(t.depth.monotonic);
    EXPECT_GT(t.depth.intervals.count, 0u);
}

// ---- the gadget's controls through uvcvideo ------------------------------------------------------

// The feeder's controls (uvcfeeder.c): brightness -64..64, default 0, whose offset from the default is added
// to the depth pattern; the auto-exposure mode offers manual and aperture priority (its default).
constexpr std::int64_t kBrightnessMin = -64;
constexpr std::int64_t kBrightnessMax = 64;
constexpr std::int64_t kBrightnessDefault = 0;
constexpr std::int64_t kAutoExposureDefault = V4L2_EXPOSURE_APERTURE_PRIORITY;

// A control's value as the driver reports it now.
std::optional<std::int64_t> controlValue(const std::string& path, std::uint32_t id) {
    v4l2::V4l2Node node;
    if (node.open(path) != 0)
        return std::nullopt;
    const auto controls = v4l2::queryControls(v4l2::systemSyscalls(), node.fd(), path);
    if (!controls)
        return std::nullopt;
    for (const v4l2::V4l2Control& c : *controls)
        if (c.id == id)
            return c.value;
    return std::nullopt;
}

// Which of the brightness offsets a depth frame's pixels are the pattern under.
std::optional<int> shownOffset(const frame::Frame& f, std::initializer_list<int> offsets) {
    for (const int offset : offsets)
        if (patternFrame(f.sceneDepth->depthMeters, kD435Scale, offset))
            return offset;
    return std::nullopt;
}

// Captures until `count` frames show brightness offset `to`. Frames the feeder made before the change
// reached it show `from`: up to uvcvideo's 4 buffers and the gadget's few, 4 seen under a CPU hog. None
// after the first that shows `to` goes back.
void expectFramesTurnTo(Device& device, int from, int to, int count) {
    int shown = 0, before = 0;
    while (shown < count) {
        const CaptureResult r = nextCapture(device);
        ASSERT_TRUE(r.kind == CaptureResult::Kind::Frame || r.kind == CaptureResult::Kind::Error)
            << "no frame (" << static_cast<int>(r.kind) << "): " << r.message;
        if (r.kind != CaptureResult::Kind::Frame)
            continue;
        const std::optional<int> offset = shownOffset(*r.frame, {from, to});
        ASSERT_TRUE(offset) << "frame " << feederNumber(*r.frame) << " is the pattern under neither offset "
                            << from << " nor " << to;
        if (*offset == to) {
            ++shown;
            continue;
        }
        ASSERT_EQ(shown, 0) << "frame " << feederNumber(*r.frame) << " went back to offset " << from;
        ASSERT_LT(++before, 12) << "offset " << to << " never reached the pixels";
    }
    std::printf("brightness offset %d on %d frames, %d in flight before it\n", to, shown, before);
}

SensorControl findControl(const SensorControlNode& node, std::uint32_t id) {
    const auto it = std::find_if(node.controls.begin(), node.controls.end(),
                                 [id](const SensorControl& c) { return c.id == id; });
    return it == node.controls.end() ? SensorControl{} : *it;
}

// The window's Camera controls read the feeder's ranges through uvcvideo, and a brightness set there goes
// to the feeder as SET_CUR and changes the pixels of the frames that arrive after it.
TEST(Uvc, BrightnessSetThroughUvcvideoChangesTheDepthPixels) {
    auto device = openLiveSourceSpec("usb:8086:0b07:color=none");
    ASSERT_TRUE(device) << device.error().message;
    auto& uvc = dynamic_cast<UvcDevice&>(**device);
    ASSERT_TRUE(uvc.open());
    ASSERT_TRUE(uvc.start());
    const std::string depth = uvc.depthNodePath();
    const std::shared_ptr<SensorControls> controls = uvc.sensorControls();
    ASSERT_TRUE(controls);
    const auto nodes = controls->read();
    ASSERT_TRUE(nodes) << nodes.error().message;
    const auto node =
        std::find_if(nodes->begin(), nodes->end(), [&](const auto& n) { return n.path == depth; });
    ASSERT_NE(node, nodes->end());
    const SensorControl brightness = findControl(*node, V4L2_CID_BRIGHTNESS);
    EXPECT_EQ(brightness.kind, SensorControl::Kind::Integer);
    EXPECT_EQ(brightness.minimum, kBrightnessMin);
    EXPECT_EQ(brightness.maximum, kBrightnessMax);
    EXPECT_EQ(brightness.defaultValue, kBrightnessDefault);
    EXPECT_EQ(brightness.value, kBrightnessDefault);
    const SensorControl exposure = findControl(*node, V4L2_CID_EXPOSURE_AUTO);
    EXPECT_EQ(exposure.kind, SensorControl::Kind::Menu);
    EXPECT_EQ(exposure.defaultValue, kAutoExposureDefault);
    const std::vector<std::pair<std::int64_t, std::string>> modes{
        {V4L2_EXPOSURE_MANUAL, "Manual Mode"}, {kAutoExposureDefault, "Aperture Priority Mode"}};
    EXPECT_EQ(exposure.menu, modes) << "the modes the feeder's GET_RES offers";

    ASSERT_NO_FATAL_FAILURE(expectFramesTurnTo(uvc, 0, 0, 2)) << "the plain pattern at the default";
    int from = 0;
    for (const int to : {23, -41, 0}) {
        ASSERT_TRUE(controls->set(depth, V4L2_CID_BRIGHTNESS, to));
        EXPECT_EQ(controlValue(depth, V4L2_CID_BRIGHTNESS), to);
        ASSERT_NO_FATAL_FAILURE(expectFramesTurnTo(uvc, from, to, 3));
        from = to;
    }
    uvc.close();
}

// The camera's control values as `depthcloud controls --save` writes them.
void savePreset(const std::vector<std::string>& paths, const std::string& file) {
    v4l2::ControlPreset preset{"usb:8086:0b07", {}};
    for (const std::string& path : paths) {
        v4l2::V4l2Node node;
        ASSERT_EQ(node.open(path), 0) << path;
        const auto controls = v4l2::queryControls(v4l2::systemSyscalls(), node.fd(), path);
        ASSERT_TRUE(controls) << controls.error().message;
        preset.nodes.push_back(v4l2::presetNodeOf(node.capability().card, *controls));
    }
    ASSERT_TRUE(base::writeTextFile(file, v4l2::presetJson(preset)));
}

std::optional<LiveDeviceInfo> listedCamera() {
    LiveDeviceListing listing = listLiveDevices();
    for (LiveDeviceInfo& d : listing.devices)
        if (d.usb && d.usb->id() == "8086:0b07")
            return std::move(d);
    return std::nullopt;
}

// Unbinds the gadget from its UDC and binds it again; returns the camera once its depth and colour nodes are
// listed again.
std::optional<LiveDeviceInfo> replugCamera() {
    if (!writeSysfs(env("UDC_FILE"), "") || !waitFor([] { return !listedCamera(); }, 20s) ||
        !writeSysfs(env("UDC_FILE"), env("UDC_NAME")))
        return std::nullopt;
    std::optional<LiveDeviceInfo> camera;
    waitFor(
        [&] {
            camera = listedCamera();
            return camera && !camera->depthNode.empty() && !camera->colorNode.empty();
        },
        30s);
    return camera;
}

// A preset saved, the camera unplugged (a replugged camera is at its defaults again) and plugged in, the
// preset given as preset= sets the same values when the source opens, before the first frame.
TEST(Uvc, APresetSavedIsAppliedWhenTheCameraOpensAfterAReplug) {
    ASSERT_FALSE(env("UDC_FILE").empty());
    const std::string spec = "usb:8086:0b07:color=none";
    auto config = parseLiveSourceSpec(spec);
    ASSERT_TRUE(config) << config.error().message;
    const auto paths = cameraNodePaths(*config);
    ASSERT_TRUE(paths) << paths.error().message;
    const auto before = listedCamera();
    ASSERT_TRUE(before);
    v4l2::V4l2SensorControls controls(v4l2::systemSyscalls(), *paths);
    ASSERT_TRUE(controls.set(before->depthNode, V4L2_CID_BRIGHTNESS, 37));
    ASSERT_TRUE(controls.set(before->depthNode, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL));
    const std::string path = std::filesystem::temp_directory_path() / "uvc-preset.json";
    ASSERT_NO_FATAL_FAILURE(savePreset(*paths, path));

    const auto after = replugCamera();
    ASSERT_TRUE(after) << "the camera came back";
    EXPECT_EQ(controlValue(after->depthNode, V4L2_CID_BRIGHTNESS), kBrightnessDefault) << "at its defaults";
    EXPECT_EQ(controlValue(after->depthNode, V4L2_CID_EXPOSURE_AUTO), kAutoExposureDefault);
    auto device = openLiveSourceSpec(spec + ":preset=" + path);
    ASSERT_TRUE(device) << device.error().message;
    auto& uvc = dynamic_cast<UvcDevice&>(**device);
    ASSERT_TRUE(uvc.open());
    EXPECT_EQ(controlValue(uvc.depthNodePath(), V4L2_CID_BRIGHTNESS), 37);
    EXPECT_EQ(controlValue(uvc.depthNodePath(), V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
    ASSERT_TRUE(uvc.start());
    ASSERT_NO_FATAL_FAILURE(expectFramesTurnTo(uvc, 37, 37, 3))
        << "every frame under the preset's brightness";
    // The checks after this one start from the camera's defaults.
    const std::shared_ptr<SensorControls> reopened = uvc.sensorControls();
    ASSERT_TRUE(reopened);
    EXPECT_TRUE(reopened->set(uvc.depthNodePath(), V4L2_CID_BRIGHTNESS, kBrightnessDefault));
    EXPECT_TRUE(reopened->set(uvc.depthNodePath(), V4L2_CID_EXPOSURE_AUTO, kAutoExposureDefault));
    uvc.close();
}

// ---- v4l2loopback Z16 and vivid Y16 --------------------------------------------------------------

TEST(Loopback, Z16FramesArriveInMetersPixelForPixel) {
    ASSERT_FALSE(env("LOOP_NODE").empty());
    auto device = openLiveSourceSpec("v4l2:" + env("LOOP_NODE") + ":scale=0.001");
    ASSERT_TRUE(device) << device.error().message;
    ASSERT_TRUE((*device)->open());
    ASSERT_TRUE((*device)->start());
    expectPatternFrames(**device, 5, 0.001f);
    (*device)->close();
}

TEST(Vivid, Y16IsDepthWithTheConfiguredScale) {
    ASSERT_FALSE(env("VIVID_NODE").empty());
    std::ifstream in(env("VIVID_RAW"), std::ios::binary);
    const std::vector<std::uint8_t> raw((std::istreambuf_iterator<char>(in)), {});
    const std::size_t frameBytes = static_cast<std::size_t>(kWidth) * kHeight * 2;
    ASSERT_GE(raw.size(), 2 * frameBytes) << "two reference frames from v4l2-ctl";
    ASSERT_TRUE(std::equal(raw.begin(), raw.begin() + static_cast<long>(frameBytes),
                           raw.begin() + static_cast<long>(frameBytes)))
        << "vivid's pattern is static without its on-screen text";
    constexpr float kScale = 0.0001f;
    auto device =
        openLiveSourceSpec("v4l2:" + env("VIVID_NODE") + ":640x480:format=Y16:scale=0.0001:color=none");
    ASSERT_TRUE(device) << device.error().message;
    ASSERT_TRUE((*device)->open());
    ASSERT_TRUE((*device)->start());
    CaptureResult r;
    for (int i = 0; i < 5 && r.kind != CaptureResult::Kind::Frame; ++i)
        r = (*device)->capture(5000ms);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    const frame::Plane<float>& meters = r.frame->sceneDepth->depthMeters;
    ASSERT_EQ(meters.width, kWidth);
    int nonZero = 0;
    for (std::size_t i = 0; i < meters.pixels.size(); ++i) {
        const auto value = static_cast<std::uint16_t>(raw[2 * i] | (raw[2 * i + 1] << 8));
        ASSERT_EQ(meters.pixels[i], static_cast<float>(value) * kScale) << "pixel " << i;
        nonZero += value != 0;
    }
    EXPECT_GT(nonZero, kWidth * kHeight / 2) << "the pattern is not blank";
    (*device)->close();
}

// ---- vivid's controls, as v4l2-ctl lists them -------------------------------------------------------

// One control of `v4l2-ctl --list-ctrls-menus`: "  brightness 0x00980900 (int) : min=0 max=255 step=1
// default=128 value=128 flags=slider", its menu entries on the lines after it ("  1: Menu Item 1").
struct ListedControl {
    std::uint32_t id = 0;
    std::string key;
    std::string type;
    std::map<std::string, std::string> fields; // min, max, step, default, value
    std::vector<std::pair<std::int64_t, std::string>> menu;
};

std::vector<ListedControl> parseV4l2CtlListing(std::istream& in) {
    std::vector<ListedControl> controls;
    const std::regex control(R"(^\s*(\S+) (0x[0-9a-f]+) \((\w+)\)\s*:(.*)$)");
    const std::regex entry(R"(^\s+(\d+): (.*)$)");
    const std::regex field(R"((\w+)=(\S+))");
    std::string line;
    std::smatch m;
    while (std::getline(in, line)) {
        if (std::regex_match(line, m, control)) {
            ListedControl c{static_cast<std::uint32_t>(std::stoul(m[2], nullptr, 16)), m[1], m[3], {}, {}};
            const std::string rest = m[4];
            // Flags come last, their names joined by ", ".
            const std::size_t flagsAt = std::min(rest.find("flags="), rest.size());
            const std::string numbers = rest.substr(0, flagsAt);
            for (auto f = std::sregex_iterator(numbers.begin(), numbers.end(), field);
                 f != std::sregex_iterator(); ++f)
                c.fields[(*f)[1]] = (*f)[2];
            if (flagsAt < rest.size()) {
                std::string flags = rest.substr(flagsAt + 6);
                std::erase(flags, ' ');
                c.fields["flags"] = flags;
            }
            controls.push_back(std::move(c));
        } else if (std::regex_match(line, m, entry) && !controls.empty()) {
            controls.back().menu.emplace_back(std::stoll(m[1]), m[2]);
        }
    }
    return controls;
}

std::int64_t numberOf(const std::string& text) {
    return text.starts_with("0x") ? static_cast<std::int64_t>(std::stoull(text, nullptr, 16))
                                  : std::stoll(text);
}

// Each integer-like field v4l2-ctl printed equals ours.
void expectSameFields(const ListedControl& listed, const v4l2::V4l2Control& ours) {
    const std::map<std::string, std::optional<std::int64_t>> mine{
        {"min", ours.minimum},
        {"max", ours.maximum},
        {"step", static_cast<std::int64_t>(ours.step)},
        {"default", ours.defaultValue},
        {"value", ours.value}};
    for (const auto& [name, text] : listed.fields) {
        const auto it = mine.find(name);
        // A volatile or read-only control's value is the driver's to change (vivid's gain under automatic
        // gain; its read-only integer counts the frames streamed since the listing was taken).
        const bool changesAlone =
            (ours.flags & V4L2_CTRL_FLAG_VOLATILE) || ours.readOnly() || listed.type == "button";
        if (it == mine.end() || (name == "value" && changesAlone))
            continue;
        ASSERT_TRUE(it->second.has_value()) << listed.key << " has no " << name;
        // v4l2-ctl prints a bitmask's value as a signed int; its 32 bits are unsigned, as its range is.
        if (listed.type == "bitmask")
            EXPECT_EQ(static_cast<std::uint32_t>(*it->second), static_cast<std::uint32_t>(numberOf(text)))
                << listed.key << " " << name;
        else
            EXPECT_EQ(*it->second, numberOf(text)) << listed.key << " " << name;
    }
}

TEST(Vivid, ControlsAreListedAsV4l2CtlListsThem) {
    ASSERT_FALSE(env("VIVID_CTRLS").empty());
    std::ifstream in(env("VIVID_CTRLS"));
    const std::vector<ListedControl> listed = parseV4l2CtlListing(in);
    ASSERT_GT(listed.size(), 10u) << "vivid has its user controls and a class of test controls";
    v4l2::V4l2Node node;
    ASSERT_EQ(node.open(env("VIVID_NODE")), 0);
    const auto ours = v4l2::queryControls(v4l2::systemSyscalls(), node.fd(), node.path());
    ASSERT_TRUE(ours) << ours.error().message;
    std::size_t compared = 0, menus = 0;
    for (const ListedControl& l : listed) {
        const auto it = std::find_if(ours->begin(), ours->end(), [&](const auto& c) { return c.id == l.id; });
        ASSERT_NE(it, ours->end()) << l.key << " is missing";
        EXPECT_EQ(v4l2::controlKey(it->name), l.key);
        if (it->settable() || it->readOnly()) {
            EXPECT_EQ(v4l2::controlTypeName(it->type), l.type) << l.key;
            expectSameFields(l, *it);
            const std::string flags = l.fields.count("flags") ? "," + l.fields.at("flags") + "," : "";
            for (const std::string& flag : v4l2::controlFlagNames(*it))
                EXPECT_NE(flags.find("," + flag + ","), std::string::npos) << l.key << " " << flag;
            ++compared;
        }
        if (!l.menu.empty()) {
            ASSERT_EQ(it->menu.size(), l.menu.size()) << l.key;
            for (std::size_t i = 0; i < l.menu.size(); ++i) {
                EXPECT_EQ(it->menu[i].index, l.menu[i].first) << l.key;
                // An integer menu's entry is "16 (0x10)" there, "16" here.
                EXPECT_TRUE(l.menu[i].second.starts_with(it->menu[i].label))
                    << l.key << ": " << l.menu[i].second;
            }
            ++menus;
        }
    }
    const auto classes = std::count_if(ours->begin(), ours->end(), [](const auto& c) { return c.isClass(); });
    EXPECT_EQ(ours->size() - static_cast<std::size_t>(classes), listed.size())
        << "no control v4l2-ctl leaves out";
    EXPECT_GT(compared, 10u);
    EXPECT_GE(menus, 2u) << "a menu and an integer menu";
}

// ---- a preset given as preset= is applied when the source opens ------------------------------------

std::optional<std::int64_t> vividValue(const std::string& key) {
    v4l2::V4l2Node node;
    if (node.open(env("VIVID_NODE")) != 0)
        return std::nullopt;
    const auto controls = v4l2::queryControls(v4l2::systemSyscalls(), node.fd(), node.path());
    if (!controls)
        return std::nullopt;
    for (const v4l2::V4l2Control& c : *controls)
        if (!c.isClass() && v4l2::controlKey(c.name) == key)
            return c.value;
    return std::nullopt;
}

// Sets vivid's brightness and contrast, as another program would.
void setVivid(std::int64_t brightness, std::int64_t contrast) {
    const v4l2::ControlPreset values{
        "",
        {{"vivid", {{"brightness", std::to_string(brightness)}, {"contrast", std::to_string(contrast)}}}}};
    ASSERT_TRUE(v4l2::applyPreset(v4l2::systemSyscalls(), values, {env("VIVID_NODE")}).empty());
    ASSERT_EQ(vividValue("brightness"), brightness);
}

// Opens vivid as a depth source with preset=`path`.
void openVividWithPreset(const std::string& path) {
    auto device =
        openLiveSourceSpec("v4l2:" + env("VIVID_NODE") + ":640x480:format=Y16:color=none:preset=" + path);
    ASSERT_TRUE(device) << device.error().message;
    ASSERT_TRUE((*device)->open());
    (*device)->close();
}

TEST(Vivid, APresetSavedIsAppliedWhenTheSourceOpensAndARefusedValueLeavesTheRest) {
    ASSERT_FALSE(env("VIVID_NODE").empty());
    setVivid(77, 55);
    v4l2::V4l2Node node;
    ASSERT_EQ(node.open(env("VIVID_NODE")), 0);
    const auto controls = v4l2::queryControls(v4l2::systemSyscalls(), node.fd(), node.path());
    ASSERT_TRUE(controls) << controls.error().message;
    v4l2::ControlPreset preset{"vivid", {v4l2::presetNodeOf("vivid", *controls)}};
    ASSERT_GT(preset.nodes[0].values.size(), 10u) << "vivid's writable controls";
    const std::string path = std::filesystem::temp_directory_path() / "vivid-preset.json";
    ASSERT_TRUE(base::writeTextFile(path, v4l2::presetJson(preset)));
    setVivid(10, 20);
    openVividWithPreset(path);
    EXPECT_EQ(vividValue("brightness"), 77);
    EXPECT_EQ(vividValue("contrast"), 55);

    preset.nodes[0].values = {{"brightness", "300"}, {"contrast", "66"}};
    ASSERT_TRUE(base::writeTextFile(path, v4l2::presetJson(preset)));
    openVividWithPreset(path);
    EXPECT_EQ(vividValue("brightness"), 77) << "300 is out of brightness's range: refused, left as it was";
    EXPECT_EQ(vividValue("contrast"), 66) << "the value after the refused one is set";
}

// What the Camera controls panel reads and sets (Device::sensorControls) is the driver's own.
TEST(Vivid, TheCameraControlsOfTheWindowReadAndSetTheDriversValues) {
    ASSERT_FALSE(env("VIVID_NODE").empty());
    auto device = openLiveSourceSpec("v4l2:" + env("VIVID_NODE") + ":640x480:format=Y16:color=none");
    ASSERT_TRUE(device) << device.error().message;
    const std::shared_ptr<SensorControls> controls = (*device)->sensorControls();
    ASSERT_TRUE(controls);
    const auto nodes = controls->read();
    ASSERT_TRUE(nodes) << nodes.error().message;
    ASSERT_EQ(nodes->size(), 1u);
    const auto find = [&](const std::string& key) {
        const auto& list = nodes->front().controls;
        const auto it = std::find_if(list.begin(), list.end(),
                                     [&](const SensorControl& c) { return v4l2::controlKey(c.name) == key; });
        return it == list.end() ? SensorControl{} : *it;
    };
    const SensorControl brightness = find("brightness");
    EXPECT_EQ(brightness.kind, SensorControl::Kind::Integer);
    EXPECT_EQ(brightness.maximum, 255);
    EXPECT_EQ(brightness.value, vividValue("brightness"));
    EXPECT_EQ(find("gain").inactive, vividValue("gain_automatic") == 1) << "automatic gain decides the gain";
    EXPECT_EQ(find("user_controls").kind, SensorControl::Kind::Heading);
    ASSERT_TRUE(controls->set(nodes->front().path, brightness.id, 99));
    EXPECT_EQ(vividValue("brightness"), 99);
    const Status refused = controls->set(nodes->front().path, brightness.id, 300);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("'brightness' takes 0..255, not 300"), std::string::npos)
        << refused.error().message;
    EXPECT_EQ(vividValue("brightness"), 99);

    // The panel asks changed() every frame: a change by another program arrives as V4L2_EVENT_CTRL.
    EXPECT_FALSE(controls->changed()) << "the first call starts watching";
    EXPECT_FALSE(controls->changed()) << "nothing changed since";
    setVivid(42, 43);
    EXPECT_TRUE(waitFor([&] { return controls->changed(); }, 2s)) << "another program's change is an event";
    EXPECT_FALSE(controls->changed()) << "each change is told once";
}

// The Camera controls panel's mode list: what the driver enumerates, and a mode chosen from it streams
// once the source is opened again with it.
TEST(Vivid, ADepthModeFromTheListStreamsAtItsSize) {
    ASSERT_FALSE(env("VIVID_NODE").empty());
    const std::string spec = "v4l2:" + env("VIVID_NODE") + ":640x480:format=Y16:color=none";
    auto device = openLiveSourceSpec(spec);
    ASSERT_TRUE(device) << device.error().message;
    const std::vector<StreamMode> modes = (*device)->sensorControls()->depthModes();
    const auto other = std::find_if(modes.begin(), modes.end(), [](const StreamMode& m) {
        return m.format == "Y16" && m.width != 640 && m.width <= 1280;
    });
    ASSERT_NE(other, modes.end()) << modes.size() << " modes listed, none Y16 of another size";
    EXPECT_TRUE(std::any_of(modes.begin(), modes.end(),
                            [](const StreamMode& m) { return m.width == 640 && m.height == 480; }));
    const auto chosen = specWithDepthMode(spec, *other);
    ASSERT_TRUE(chosen) << chosen.error().message;
    auto reopened = openLiveSourceSpec(*chosen);
    ASSERT_TRUE(reopened) << reopened.error().message;
    ASSERT_TRUE((*reopened)->open());
    ASSERT_TRUE((*reopened)->start());
    CaptureResult r;
    for (int i = 0; i < 5 && r.kind != CaptureResult::Kind::Frame; ++i)
        r = (*reopened)->capture(5000ms);
    ASSERT_EQ(r.kind, CaptureResult::Kind::Frame) << r.message;
    EXPECT_EQ(r.frame->sceneDepth->depthMeters.width, other->width) << *chosen;
    EXPECT_EQ(r.frame->sceneDepth->depthMeters.height, other->height) << *chosen;
    (*reopened)->close();
}

// ---- cameras that are not on USB, seen by the picker through udev alone ----------------------------

// The drivers of the depth nodes the picker lists now (when it published a new listing).
bool pickerShowsDriver(LiveDeviceWatcher& watcher, std::vector<std::string>& drivers,
                       const std::string& driver) {
    if (auto listing = watcher.takeUpdate()) {
        drivers.clear();
        for (const LiveDeviceInfo& d : listing->devices)
            for (const VideoNodeInfo& node : d.nodes)
                if (node.path == d.depthNode)
                    drivers.push_back(node.driver);
    }
    return std::find(drivers.begin(), drivers.end(), driver) != drivers.end();
}

// Asks init.sh, outside the chroot where the guest's modules are, to unplug or replug the loopback camera
// (module and feeder) and waits until it has.
bool askForLoopback(const std::string& what) {
    const std::string request = env("LOOP_REQUEST");
    if (request.empty() || !writeSysfs(request, what))
        return false;
    return waitFor([&] { return !std::ifstream(request).good(); }, 30s);
}

TEST(Virtual, ThePickerFollowsLoopbackAndVividWithoutPolling) {
    ASSERT_FALSE(env("LOOP_NODE").empty());
    ASSERT_FALSE(env("VIVID_NODE").empty());
    LiveDeviceWatcher picker(std::chrono::hours(1)); // polling only as a fallback, which must not happen here
    ASSERT_TRUE(picker.watchingEvents()) << "udev's monitor drives the device picker";
    std::vector<std::string> drivers;
    const auto shows = [&](const char* driver) { return pickerShowsDriver(picker, drivers, driver); };
    ASSERT_TRUE(waitFor([&] { return shows("vivid") && shows("v4l2 loopback"); }, 20s)) << "listed at start";

    const std::string vivid = "/sys/bus/platform/drivers/vivid/";
    ASSERT_TRUE(writeSysfs(vivid + "unbind", "vivid.0"));
    EXPECT_TRUE(waitFor([&] { return !shows("vivid"); }, 20s)) << "vivid's node went away";
    ASSERT_TRUE(writeSysfs(vivid + "bind", "vivid.0"));
    EXPECT_TRUE(waitFor([&] { return shows("vivid"); }, 20s)) << "vivid's node came back";

    ASSERT_TRUE(askForLoopback("unplug"));
    EXPECT_TRUE(waitFor([&] { return !shows("v4l2 loopback"); }, 20s)) << "the loopback camera went away";
    ASSERT_TRUE(askForLoopback("replug"));
    EXPECT_TRUE(waitFor([&] { return shows("v4l2 loopback"); }, 20s)) << "the loopback camera came back";
}

} // namespace
} // namespace dc::devices
