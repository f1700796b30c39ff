// A RealSense D4xx's emitter and laser power, reached through its depth extension unit (UVCIOC_CTRL_QUERY)
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
    ASSERT_EQ(listed.size(), 2u);
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
    ASSERT_EQ(listed.size(), 2u);
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
    ASSERT_EQ(listed.size(), 1u);
    EXPECT_EQ(controlKey(listed[0].name), "laser_power");
    // A size other than the one we know: another firmware's meaning, not trusted.
    xu_.controls[{kUnit, kLaserPower}].size = 4;
    EXPECT_TRUE(read(controls).empty());
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
        controls.changed();
        const ControlPreset preset{"", {{"", {{"laser_power", "150"}}}}};
        EXPECT_EQ(applyPreset(xu_, preset, {kDepth}, none).size(), 1u) << "no such control";
    }
    EXPECT_TRUE(xu_.sent.empty());
}

TEST_F(XuControls, PresetsSaveAndApplyThemByName) {
    auto listed = queryNodeControls(xu_, 0, kDepth, d435());
    ASSERT_TRUE(listed.ok());
    const PresetNode saved = presetNodeOf("Intel RealSense D435", *listed);
    const std::vector<std::pair<std::string, std::string>> values{{"emitter_enabled", "Laser"},
                                                                  {"laser_power", "150"}};
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
