// A RealSense D4xx's emitter, laser power and depth exposure (manual and auto), reached through its depth
// extension unit (UVCIOC_CTRL_QUERY)
// and shown among the node's V4L2 controls; and no XU request at all to a camera the known-camera table
// does not mark as a D4xx. The fake XU answers as uvcvideo passes a D435's answers on.

#include "devices/uvc/uvc_device.h"
#include "devices/uvc/v4l2/control_preset.h"
#include "devices/uvc/v4l2/xu_controls.h"
#include "tests/unit/live/fake_v4l2.h"

#include <gtest/gtest.h>
#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <unistd.h>

namespace dc::devices::v4l2 {
namespace {

namespace fs = std::filesystem;
using testing::FakeV4l2;

constexpr const char* kDepth = "/dev/video0";
constexpr std::uint8_t kUnit = 3;
constexpr std::uint8_t kEmitter = 2;
constexpr std::uint8_t kLaserPower = 4;
constexpr std::uint8_t kExposure = 3;
constexpr std::uint8_t kAutoExposure = 0x0b;

// One query as the camera received it.
struct SentQuery {
    std::uint8_t unit = 0;
    std::uint8_t selector = 0;
    std::uint8_t query = 0;
    std::vector<std::uint8_t> bytes; // what SET_CUR carried
};

// The depth XU of a D435 in front of FakeV4l2's nodes: values little-endian in GET_LEN's size, as the
// camera's firmware answers them. The nodes have no V4L2 controls (VIDIOC_QUERY_EXT_CTRL: EINVAL at once).
class FakeXu final : public Syscalls {
public:
    struct Control {
        std::uint8_t info = UVC_CONTROL_CAP_GET | UVC_CONTROL_CAP_SET;
        std::uint16_t size = 0;
        std::uint32_t minimum = 0, maximum = 0, resolution = 0, defaultValue = 0, current = 0;
        bool infoFails = false;
        std::optional<std::uint32_t> keeps{}; // a firmware that takes SET_CUR and keeps this value instead
    };

    explicit FakeXu(FakeV4l2& v4l2) : v4l2_(v4l2) {
        // D435: the emitter off / laser / laser auto, laser power 0..360 mW in steps of 30.
        controls[{kUnit, kEmitter}] = {
            .size = 1, .maximum = 2, .resolution = 1, .defaultValue = 1, .current = 1};
        controls[{kUnit, kLaserPower}] = {
            .size = 2, .maximum = 360, .resolution = 30, .defaultValue = 150, .current = 150};
        // Auto exposure on; the manual exposure 1..165000 us (past 16 bits), 8.5 ms by default.
        controls[{kUnit, kAutoExposure}] = {
            .size = 1, .maximum = 1, .resolution = 1, .defaultValue = 1, .current = 1};
        controls[{kUnit, kExposure}] = {.size = 4,
                                        .minimum = 1,
                                        .maximum = 165000,
                                        .resolution = 1,
                                        .defaultValue = 8500,
                                        .current = 8500};
    }

    std::map<std::pair<std::uint8_t, std::uint8_t>, Control> controls;
    std::vector<SentQuery> sent;

    int open(const char* path, int flags) override { return v4l2_.open(path, flags); }
    int close(int fd) override { return v4l2_.close(fd); }
    int ioctl(int fd, unsigned long request, void* arg) override {
        if (request == UVCIOC_CTRL_QUERY)
            return query(*static_cast<uvc_xu_control_query*>(arg));
        if (request == VIDIOC_QUERY_EXT_CTRL)
            return -EINVAL;
        return v4l2_.ioctl(fd, request, arg);
    }
    int mmap(void** address, std::size_t length, int prot, int fd, off_t offset) override {
        return v4l2_.mmap(address, length, prot, fd, offset);
    }
    int munmap(void* address, std::size_t length) override { return v4l2_.munmap(address, length); }
    int poll(pollfd* fds, nfds_t count, int timeoutMs) override { return v4l2_.poll(fds, count, timeoutMs); }
    ssize_t read(int fd, void* buffer, std::size_t size) override { return v4l2_.read(fd, buffer, size); }
    ssize_t write(int fd, const void* buffer, std::size_t size) override {
        return v4l2_.write(fd, buffer, size);
    }
    int eventfd(unsigned initialValue, int flags) override { return v4l2_.eventfd(initialValue, flags); }

private:
    static int put(const uvc_xu_control_query& q, std::uint32_t value) {
        for (std::size_t i = 0; i < q.size; ++i)
            q.data[i] = static_cast<std::uint8_t>(value >> (8 * i));
        return 0;
    }

    // uvcvideo's answers: ENOENT for a unit or selector the camera lacks, ENOBUFS for a size other than
    // the control's, EIO for a request the camera stalls.
    int query(const uvc_xu_control_query& q) {
        sent.push_back({q.unit, q.selector, q.query, {}});
        const auto found = controls.find({q.unit, q.selector});
        if (found == controls.end())
            return -ENOENT;
        Control& c = found->second;
        switch (q.query) {
        case UVC_GET_INFO:
            if (c.infoFails || q.size != 1)
                return -EIO;
            return put(q, c.info);
        case UVC_GET_LEN:
            return q.size != 2 ? -ENOBUFS : put(q, c.size);
        case UVC_SET_CUR:
            if (q.size != c.size || !(c.info & UVC_CONTROL_CAP_SET))
                return -EIO;
            sent.back().bytes.assign(q.data, q.data + q.size);
            c.current = 0;
            for (std::size_t i = 0; i < q.size; ++i)
                c.current |= static_cast<std::uint32_t>(q.data[i]) << (8 * i);
            c.current = c.keeps.value_or(c.current);
            return 0;
        default:
            break;
        }
        if (q.size != c.size)
            return -ENOBUFS;
        const std::map<std::uint8_t, std::uint32_t> values{{UVC_GET_MIN, c.minimum},
                                                           {UVC_GET_MAX, c.maximum},
                                                           {UVC_GET_RES, c.resolution},
                                                           {UVC_GET_DEF, c.defaultValue},
                                                           {UVC_GET_CUR, c.current}};
        const auto value = values.find(q.query);
        return value == values.end() ? -EINVAL : put(q, value->second);
    }

    FakeV4l2& v4l2_;
};

XuAccess d435() {
    return xuAccessFor(0x8086, 0x0b07, kDepth);
}

class XuControls : public ::testing::Test {
protected:
    void SetUp() override { v4l2_.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, 4, 3, {30}}}}); }

    std::vector<SensorControl> read(SensorControls& controls) {
        auto nodes = controls.read();
        EXPECT_TRUE(nodes.ok()) << nodes.error().message;
        return nodes.ok() && !nodes->empty() ? nodes->front().controls : std::vector<SensorControl>{};
    }

    static const SensorControl* named(const std::vector<SensorControl>& controls, const std::string& key) {
        const auto c = std::find_if(controls.begin(), controls.end(),
                                    [&key](const SensorControl& s) { return controlKey(s.name) == key; });
        return c == controls.end() ? nullptr : &*c;
    }

    FakeV4l2 v4l2_;
    FakeXu xu_{v4l2_};
};

TEST_F(XuControls, AD4xxListsItsEmitterAndLaserPowerWithTheirRanges) {
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls);
    ASSERT_EQ(listed.size(), 4u);
    const SensorControl* emitter = named(listed, "emitter_enabled");
    ASSERT_NE(emitter, nullptr);
    EXPECT_EQ(emitter->kind, SensorControl::Kind::Menu);
    EXPECT_EQ(emitter->minimum, 0);
    EXPECT_EQ(emitter->maximum, 2);
    EXPECT_EQ(emitter->defaultValue, 1);
    EXPECT_EQ(emitter->value, 1);
    EXPECT_FALSE(emitter->readOnly);
    const std::vector<std::pair<std::int64_t, std::string>> menu{{0, "Off"}, {1, "Laser"}, {2, "Laser Auto"}};
    EXPECT_EQ(emitter->menu, menu);
    const SensorControl* power = named(listed, "laser_power");
    ASSERT_NE(power, nullptr);
    EXPECT_EQ(power->kind, SensorControl::Kind::Integer);
    EXPECT_EQ(power->minimum, 0);
    EXPECT_EQ(power->maximum, 360);
    EXPECT_EQ(power->step, 30);
    EXPECT_EQ(power->defaultValue, 150);
    EXPECT_EQ(power->value, 150);
}

TEST_F(XuControls, ASetSendsSetCurLittleEndianAndReadsItBack) {
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls); // named() points into it
    const SensorControl* power = named(listed, "laser_power");
    ASSERT_NE(power, nullptr);
    xu_.sent.clear();
    const Status s = controls.set(kDepth, power->id, 270);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const auto set = std::find_if(xu_.sent.begin(), xu_.sent.end(),
                                  [](const SentQuery& q) { return q.query == UVC_SET_CUR; });
    ASSERT_NE(set, xu_.sent.end());
    EXPECT_EQ(set->unit, kUnit);
    EXPECT_EQ(set->selector, kLaserPower);
    EXPECT_EQ(set->bytes, (std::vector<std::uint8_t>{0x0e, 0x01})) << "270 = 0x010e, low byte first";
    ASSERT_EQ(set + 2, xu_.sent.end()) << "one query after SET_CUR: the read back";
    EXPECT_EQ((set + 1)->query, UVC_GET_CUR);
    EXPECT_EQ((set + 1)->selector, kLaserPower);
    EXPECT_EQ(named(read(controls), "laser_power")->value, 270);
}

TEST_F(XuControls, AValueTheCameraDoesNotKeepIsAnError) {
    const std::vector<V4l2Control> listed = queryXuControls(xu_, 0, d435());
    ASSERT_EQ(listed.size(), 4u);
    xu_.controls[{kUnit, kLaserPower}].keeps = 180;
    const Status s = setXuControl(xu_, 0, kDepth, listed[1], 330);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("'laser_power' to 330"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("keeps 180"), std::string::npos) << s.error().message;
}

TEST_F(XuControls, AnOutOfRangeValueIsRefusedNamingTheControlAndNotSent) {
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls);
    xu_.sent.clear();
    const Status high = controls.set(kDepth, named(listed, "laser_power")->id, 400);
    ASSERT_FALSE(high.ok());
    EXPECT_NE(high.error().message.find("'laser_power'"), std::string::npos) << high.error().message;
    EXPECT_NE(high.error().message.find("0..360"), std::string::npos) << high.error().message;
    const Status offStep = controls.set(kDepth, named(listed, "laser_power")->id, 100);
    ASSERT_FALSE(offStep.ok());
    EXPECT_NE(offStep.error().message.find("steps of 30"), std::string::npos) << offStep.error().message;
    const Status noEntry = controls.set(kDepth, named(listed, "emitter_enabled")->id, 3);
    ASSERT_FALSE(noEntry.ok());
    EXPECT_NE(noEntry.error().message.find("'emitter_enabled'"), std::string::npos)
        << noEntry.error().message;
    EXPECT_TRUE(std::none_of(xu_.sent.begin(), xu_.sent.end(),
                             [](const SentQuery& q) { return q.query == UVC_SET_CUR; }));
}

TEST_F(XuControls, AControlThatFailsItsQueriesIsLeftOut) {
    xu_.controls[{kUnit, kEmitter}].infoFails = true;
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    std::vector<SensorControl> listed = read(controls);
    ASSERT_EQ(listed.size(), 3u);
    EXPECT_EQ(named(listed, "emitter_enabled"), nullptr);
    EXPECT_NE(named(listed, "laser_power"), nullptr);
    // A size other than the one we know: another firmware's meaning, not trusted (an exposure of 16 bits).
    xu_.controls[{kUnit, kLaserPower}].size = 4;
    xu_.controls[{kUnit, kExposure}].size = 2;
    listed = read(controls);
    ASSERT_EQ(listed.size(), 1u);
    EXPECT_EQ(controlKey(listed[0].name), "enable_auto_exposure");
}

TEST_F(XuControls, AControlWithoutSetCurIsReadOnly) {
    xu_.controls[{kUnit, kLaserPower}].info = UVC_CONTROL_CAP_GET;
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls); // named() points into it
    const SensorControl* power = named(listed, "laser_power");
    ASSERT_NE(power, nullptr);
    EXPECT_TRUE(power->readOnly);
    const Status s = controls.set(kDepth, power->id, 60);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("read-only"), std::string::npos) << s.error().message;
}

TEST_F(XuControls, ACameraNotInTheTableAsAD4xxGetsNoXuRequest) {
    for (const auto& [vendor, product] : {std::pair<std::uint16_t, std::uint16_t>{0x1234, 0x5678},
                                          {0x8086, 0x0b64} /* L515 */,
                                          {0x2bc5, 0x0401} /* Orbbec */}) {
        const XuAccess none = xuAccessFor(vendor, product, kDepth);
        EXPECT_EQ(none.unit, nullptr);
        V4l2SensorControls controls(xu_, {kDepth}, none);
        EXPECT_TRUE(read(controls).empty());
        EXPECT_FALSE(controls.set(kDepth, 0x0dc00304, 150).ok());
        EXPECT_FALSE(controls.set(kDepth, 0x0dc00303, 20000).ok()) << "the exposure's id";
        EXPECT_FALSE(controls.set(kDepth, 0x0dc0030b, 0).ok()) << "auto exposure's id";
        EXPECT_TRUE(queryXuControls(xu_, 0, none).empty());
        controls.changed();
        const ControlPreset preset{
            "",
            {{"", {{"laser_power", "150"}, {"enable_auto_exposure", "0"}, {"depth_exposure_us", "20000"}}}}};
        EXPECT_EQ(applyPreset(xu_, preset, {kDepth}, none).size(), 3u) << "no such control";
    }
    EXPECT_TRUE(xu_.sent.empty());
}

TEST_F(XuControls, PresetsSaveAndApplyThemByName) {
    auto listed = queryNodeControls(xu_, 0, kDepth, d435());
    ASSERT_TRUE(listed.ok());
    const PresetNode saved = presetNodeOf("Intel RealSense D435", *listed);
    // The exposure is left out while auto exposure decides it.
    const std::vector<std::pair<std::string, std::string>> values{
        {"emitter_enabled", "Laser"}, {"laser_power", "150"}, {"enable_auto_exposure", "1"}};
    EXPECT_EQ(saved.values, values);
    auto preset = parsePreset(presetJson({"usb:8086:0b07", {saved}}), "preset.json");
    ASSERT_TRUE(preset.ok()) << preset.error().message;
    preset->nodes[0].values = {{"emitter_enabled", "laser auto"}, {"laser_power", "300"}};
    const std::vector<std::string> refused = applyPreset(xu_, *preset, {kDepth}, d435());
    EXPECT_TRUE(refused.empty()) << refused.front();
    EXPECT_EQ((xu_.controls[{kUnit, kEmitter}].current), 2u);
    EXPECT_EQ((xu_.controls[{kUnit, kLaserPower}].current), 300u);
    preset->nodes[0].values = {{"laser_power", "999"}};
    const std::vector<std::string> high = applyPreset(xu_, *preset, {kDepth}, d435());
    ASSERT_EQ(high.size(), 1u);
    EXPECT_NE(high[0].find("'laser_power'"), std::string::npos) << high[0];
}

// The depth sensor's exposure: auto exposure (selector 0x0B, one byte) as a boolean, the manual exposure
// (selector 3, four bytes, microseconds) with the unit's range, inactive while auto exposure is on, after
// auto exposure so that a preset turns that off first.
TEST_F(XuControls, AD4xxListsItsExposureAndAutoExposureWithTheUnitsRanges) {
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    std::vector<SensorControl> listed = read(controls);
    const SensorControl* automatic = named(listed, "enable_auto_exposure");
    ASSERT_NE(automatic, nullptr);
    EXPECT_EQ(automatic->kind, SensorControl::Kind::Boolean);
    EXPECT_EQ(automatic->minimum, 0);
    EXPECT_EQ(automatic->maximum, 1);
    EXPECT_EQ(automatic->defaultValue, 1);
    EXPECT_EQ(automatic->value, 1);
    EXPECT_FALSE(automatic->inactive);
    const SensorControl* exposure = named(listed, "depth_exposure_us");
    ASSERT_NE(exposure, nullptr);
    EXPECT_EQ(exposure->kind, SensorControl::Kind::Integer);
    EXPECT_EQ(exposure->minimum, 1);
    EXPECT_EQ(exposure->maximum, 165000) << "all four bytes of GET_MAX";
    EXPECT_EQ(exposure->step, 1);
    EXPECT_EQ(exposure->defaultValue, 8500);
    EXPECT_EQ(exposure->value, 8500);
    EXPECT_FALSE(exposure->readOnly);
    EXPECT_TRUE(exposure->inactive) << "auto exposure decides it";
    EXPECT_LT(automatic, exposure) << "auto exposure is listed first";

    const Status off = controls.set(kDepth, automatic->id, 0);
    ASSERT_TRUE(off.ok()) << off.error().message;
    EXPECT_EQ((xu_.controls[{kUnit, kAutoExposure}].current), 0u);
    listed = read(controls);
    ASSERT_NE(named(listed, "depth_exposure_us"), nullptr);
    EXPECT_FALSE(named(listed, "depth_exposure_us")->inactive) << "settable once auto exposure is off";
    EXPECT_EQ(named(listed, "enable_auto_exposure")->value, 0);
}

TEST_F(XuControls, TheExposureIsInactiveOnlyWhileAutoExposureIsReadAndOn) {
    const auto exposureFlags = [&] {
        const std::vector<V4l2Control> listed = queryXuControls(xu_, 0, d435());
        const auto c = std::find_if(listed.begin(), listed.end(), [](const V4l2Control& v) {
            return controlKey(v.name) == "depth_exposure_us";
        });
        return c == listed.end() ? std::vector<std::string>{"missing"} : controlFlagNames(*c);
    };
    EXPECT_EQ(exposureFlags(), std::vector<std::string>{"inactive"}) << "as `controls` lists it";
    xu_.controls[{kUnit, kAutoExposure}].current = 0;
    EXPECT_TRUE(exposureFlags().empty());
    xu_.controls[{kUnit, kAutoExposure}].current = 1;
    xu_.controls[{kUnit, kAutoExposure}].infoFails = true;
    EXPECT_TRUE(exposureFlags().empty()) << "an auto control that cannot be read decides nothing";
}

TEST_F(XuControls, AnExposureSetSendsFourBytesLittleEndianAndReadsItBack) {
    xu_.controls[{kUnit, kAutoExposure}].current = 0;
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls); // named() points into it
    const SensorControl* exposure = named(listed, "depth_exposure_us");
    ASSERT_NE(exposure, nullptr);
    xu_.sent.clear();
    const Status s = controls.set(kDepth, exposure->id, 100000);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const auto set = std::find_if(xu_.sent.begin(), xu_.sent.end(),
                                  [](const SentQuery& q) { return q.query == UVC_SET_CUR; });
    ASSERT_NE(set, xu_.sent.end());
    EXPECT_EQ(set->unit, kUnit);
    EXPECT_EQ(set->selector, kExposure);
    EXPECT_EQ(set->bytes, (std::vector<std::uint8_t>{0xa0, 0x86, 0x01, 0x00})) << "100000 = 0x000186a0";
    ASSERT_EQ(set + 2, xu_.sent.end()) << "one query after SET_CUR: the read back";
    EXPECT_EQ((set + 1)->query, UVC_GET_CUR);
    EXPECT_EQ((set + 1)->selector, kExposure);
    EXPECT_EQ(named(read(controls), "depth_exposure_us")->value, 100000);

    xu_.controls[{kUnit, kExposure}].keeps = 33000;
    const Status kept = controls.set(kDepth, exposure->id, 20000);
    ASSERT_FALSE(kept.ok());
    EXPECT_NE(kept.error().message.find("'depth_exposure_us' to 20000"), std::string::npos)
        << kept.error().message;
    EXPECT_NE(kept.error().message.find("keeps 33000"), std::string::npos) << kept.error().message;
}

TEST_F(XuControls, AnExposureOutOfRangeIsRefusedNamingTheControlAndNotSent) {
    V4l2SensorControls controls(xu_, {kDepth}, d435());
    const std::vector<SensorControl> listed = read(controls);
    const SensorControl* exposure = named(listed, "depth_exposure_us");
    const SensorControl* automatic = named(listed, "enable_auto_exposure");
    ASSERT_NE(exposure, nullptr);
    ASSERT_NE(automatic, nullptr);
    xu_.sent.clear();
    for (const std::int64_t value : {0, 165001}) {
        const Status s = controls.set(kDepth, exposure->id, value);
        ASSERT_FALSE(s.ok()) << value;
        EXPECT_NE(s.error().message.find("'depth_exposure_us' takes 1..165000, not " + std::to_string(value)),
                  std::string::npos)
            << s.error().message;
    }
    const Status two = controls.set(kDepth, automatic->id, 2);
    ASSERT_FALSE(two.ok());
    EXPECT_NE(two.error().message.find("'enable_auto_exposure' takes 0..1"), std::string::npos)
        << two.error().message;
    EXPECT_TRUE(std::none_of(xu_.sent.begin(), xu_.sent.end(),
                             [](const SentQuery& q) { return q.query == UVC_SET_CUR; }));
}

TEST_F(XuControls, PresetsSaveTheExposureWhileManualAndApplyAutoExposureFirst) {
    xu_.controls[{kUnit, kAutoExposure}].current = 0;
    xu_.controls[{kUnit, kExposure}].current = 12000;
    auto listed = queryNodeControls(xu_, 0, kDepth, d435());
    ASSERT_TRUE(listed.ok());
    const PresetNode saved = presetNodeOf("Intel RealSense D435", *listed);
    const std::vector<std::pair<std::string, std::string>> values{{"emitter_enabled", "Laser"},
                                                                  {"laser_power", "150"},
                                                                  {"enable_auto_exposure", "0"},
                                                                  {"depth_exposure_us", "12000"}};
    EXPECT_EQ(saved.values, values);
    auto preset = parsePreset(presetJson({"usb:8086:0b07", {saved}}), "preset.json");
    ASSERT_TRUE(preset.ok()) << preset.error().message;
    xu_.controls[{kUnit, kAutoExposure}].current = 1;
    xu_.controls[{kUnit, kExposure}].current = 8500;
    xu_.sent.clear();
    const std::vector<std::string> refused = applyPreset(xu_, *preset, {kDepth}, d435());
    EXPECT_TRUE(refused.empty()) << refused.front();
    EXPECT_EQ((xu_.controls[{kUnit, kAutoExposure}].current), 0u);
    EXPECT_EQ((xu_.controls[{kUnit, kExposure}].current), 12000u);
    std::vector<std::uint8_t> setOrder;
    for (const SentQuery& q : xu_.sent)
        if (q.query == UVC_SET_CUR && (q.selector == kAutoExposure || q.selector == kExposure))
            setOrder.push_back(q.selector);
    EXPECT_EQ(setOrder, (std::vector<std::uint8_t>{kAutoExposure, kExposure}));
    preset->nodes[0].values = {{"depth_exposure_us", "200000"}};
    const std::vector<std::string> high = applyPreset(xu_, *preset, {kDepth}, d435());
    ASSERT_EQ(high.size(), 1u);
    EXPECT_NE(high[0].find("'depth_exposure_us'"), std::string::npos) << high[0];
}

// The USB descriptors of a camera with one VideoControl interface whose extension unit `unitId` has `guid`,
// and one VideoStreaming interface.
std::vector<std::uint8_t> descriptorsWithUnit(std::uint8_t unitId, const std::array<std::uint8_t, 16>& guid) {
    std::vector<std::uint8_t> d(18, 0);
    d[0] = 18;
    d[1] = 0x01;                                                             // device
    d.insert(d.end(), {9, 0x02, 0, 0, 2, 1, 0, 0x80, 250});                  // configuration
    d.insert(d.end(), {9, 0x04, 0, 0, 0, 0x0e, 0x01, 0, 0});                 // VideoControl interface
    d.insert(d.end(), {13, 0x24, 0x01, 0x50, 0x01, 0, 0, 0, 0, 0, 0, 1, 1}); // its header
    d.insert(d.end(), {26, 0x24, 0x06, unitId});                             // an extension unit
    d.insert(d.end(), guid.begin(), guid.end());
    d.insert(d.end(), {0, 1, 2, 1, 0, 0});
    d.insert(d.end(), {9, 0x04, 1, 0, 1, 0x0e, 0x02, 0, 0}); // VideoStreaming interface
    return d;
}

const std::array<std::uint8_t, 16> kD4xxDepthGuid{0xcb, 0x6c, 0x60, 0xc9, 0x4c, 0x59, 0x25, 0x4d,
                                                  0xaf, 0x47, 0xcc, 0xc4, 0x96, 0x43, 0x59, 0x95};

TEST(XuDescriptors, TheUnitIsDeclaredOnlyWithItsIdAndGuidInAVideoControlInterface) {
    const ExtensionUnit& unit = *d435().unit;
    EXPECT_TRUE(declaresExtensionUnit(descriptorsWithUnit(3, kD4xxDepthGuid), unit));
    EXPECT_FALSE(declaresExtensionUnit(descriptorsWithUnit(4, kD4xxDepthGuid), unit)) << "another unit id";
    std::array<std::uint8_t, 16> other = kD4xxDepthGuid;
    other[15] ^= 1;
    EXPECT_FALSE(declaresExtensionUnit(descriptorsWithUnit(3, other), unit)) << "another vendor's GUID";
    std::vector<std::uint8_t> streaming = descriptorsWithUnit(3, kD4xxDepthGuid);
    streaming[27 + 6] = 0x02; // the interface is VideoStreaming: its 0x24/0x06 is no extension unit
    EXPECT_FALSE(declaresExtensionUnit(streaming, unit));
    const std::vector<std::uint8_t> full = descriptorsWithUnit(3, kD4xxDepthGuid);
    // Cut anywhere before the unit's last byte: never read past the end, and no unit.
    const std::size_t unitEnd = 18 + 9 + 9 + 13 + 26;
    for (std::size_t size = 0; size < unitEnd; ++size)
        EXPECT_FALSE(declaresExtensionUnit(std::span(full).first(size), unit)) << size;
    EXPECT_TRUE(declaresExtensionUnit(std::span(full).first(unitEnd), unit));
    std::vector<std::uint8_t> zeroLength = full;
    zeroLength[18] = 0; // a length of 0 would loop forever
    EXPECT_FALSE(declaresExtensionUnit(zeroLength, unit));
}

// UvcDevice finds the camera's USB ids and descriptors behind its v4l2: node in sysfs: a D435 shows the XU
// controls; another camera, a device that borrows a D435's ids without its unit (as the kernel tier's UVC
// gadget does) and a camera on no USB bus (an empty sysfs) get no XU request.
class XuUvcDevice : public XuControls {
protected:
    void SetUp() override {
        XuControls::SetUp();
        sysfs_ = fs::temp_directory_path() / ("dc-xu-sysfs-" + std::to_string(::getpid()));
        fs::remove_all(sysfs_);
        fs::create_directories(sysfs_ / "class/video4linux/video0");
    }
    void TearDown() override { fs::remove_all(sysfs_); }

    void plugUsb(const char* vendor, const char* product, const std::vector<std::uint8_t>& descriptors) {
        const fs::path device = sysfs_ / "bus/usb/devices/1-1";
        fs::create_directories(device / "1-1:1.0");
        std::ofstream(device / "idVendor") << vendor << "\n";
        std::ofstream(device / "idProduct") << product << "\n";
        std::ofstream(device / "descriptors", std::ios::binary)
            .write(reinterpret_cast<const char*>(descriptors.data()), std::ssize(descriptors));
        const fs::path link = sysfs_ / "class/video4linux/video0/device";
        fs::remove(link);
        fs::create_directory_symlink(device / "1-1:1.0", link);
    }

    UvcConfig config() const {
        UvcConfig c;
        c.depthNode = kDepth;
        c.color = false;
        c.sysfsRoot = sysfs_.string();
        return c;
    }

    fs::path sysfs_;
};

TEST_F(XuUvcDevice, AD435BehindItsNodeShowsTheXuControls) {
    plugUsb("8086", "0b07", descriptorsWithUnit(3, kD4xxDepthGuid));
    UvcDevice device(config(), xu_);
    const auto controls = device.sensorControls();
    ASSERT_NE(controls, nullptr);
    const std::vector<SensorControl> listed = read(*controls);
    EXPECT_NE(named(listed, "laser_power"), nullptr);
    EXPECT_NE(named(listed, "emitter_enabled"), nullptr);
    EXPECT_NE(named(listed, "enable_auto_exposure"), nullptr);
    EXPECT_NE(named(listed, "depth_exposure_us"), nullptr);
}

TEST_F(XuUvcDevice, AnotherCameraAGadgetWithAD435sIdsOrNoUsbGetsNoXuRequest) {
    for (int camera = 0; camera < 3; ++camera) {
        if (camera == 1)
            plugUsb("2bc5", "0401", descriptorsWithUnit(3, kD4xxDepthGuid));
        if (camera == 2)
            plugUsb("8086", "0b07", descriptorsWithUnit(4, {}));
        UvcDevice device(config(), xu_);
        const auto controls = device.sensorControls();
        ASSERT_NE(controls, nullptr);
        EXPECT_TRUE(read(*controls).empty());
    }
    EXPECT_TRUE(xu_.sent.empty());
}

} // namespace
} // namespace dc::devices::v4l2
