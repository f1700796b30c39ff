#include "devices/uvc/v4l2/xu_controls.h"

#include "devices/uvc/usb/known_cameras.h"

#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>

namespace dc::devices::v4l2 {

namespace {

// Our ids for XU controls: V4L2's control ids stay below 0x01000000 (class << 16 | index) and its top bits
// are the NEXT_CTRL / NEXT_COMPOUND flags, so this range can hold no driver's control.
constexpr std::uint32_t kXuIdBase = 0x0dc00000;
constexpr std::uint32_t kXuIdMask = 0x0fff0000;

constexpr const char* kEmitterLabels[] = {"Off", "Laser", "Laser Auto", "LED"};

// RealSense D4xx's depth XU: unit 3, GUID C9606CCB-594C-4D25-AF47-CCC496435995, selectors as librealsense's
// ds-private.h numbers them. The emitter is one byte (0 off, 1 laser, 2 laser switched by the camera's auto
// exposure, 3 LED on models that have one); laser power 16 bits in milliwatts. The depth sensor's auto
// exposure is one byte (0 off, 1 on) at selector 0x0B, its manual exposure 32 bits in microseconds at
// selector 3, which auto exposure overrides while on (librealsense switches auto exposure off before it sets
// one). Ranges and defaults are the camera's answers, as librealsense takes them from GET_MIN/MAX/RES/DEF.
// Auto exposure is listed first, so that a preset turns it off before it sets the exposure.
constexpr std::uint8_t kAutoExposureSelector = 0x0b;
constexpr XuControlSpec kRealsenseDepthControls[] = {
    {"Emitter Enabled", 2, 1, V4L2_CTRL_TYPE_MENU, kEmitterLabels},
    {"Laser Power", 4, 2, V4L2_CTRL_TYPE_INTEGER, {}},
    {"Enable Auto Exposure", kAutoExposureSelector, 1, V4L2_CTRL_TYPE_BOOLEAN, {}},
    {"Depth Exposure (us)", 3, 4, V4L2_CTRL_TYPE_INTEGER, {}, kAutoExposureSelector},
};
constexpr ExtensionUnit kRealsenseDepthXu{
    3,
    {0xcb, 0x6c, 0x60, 0xc9, 0x4c, 0x59, 0x25, 0x4d, 0xaf, 0x47, 0xcc, 0xc4, 0x96, 0x43, 0x59, 0x95},
    kRealsenseDepthControls};

// USB's interface descriptor and UVC's class-specific ones (UVC 1.5, 3.7.2.7, A.2, A.4, A.5): an extension
// unit is one in a VideoControl interface, its id at byte 3 and its GUID at byte 4.
constexpr std::uint8_t kInterface = 0x04;
constexpr std::uint8_t kVideoClass = 0x0e;
constexpr std::uint8_t kVideoControlSubclass = 0x01;
constexpr std::uint8_t kCsInterface = 0x24;
constexpr std::uint8_t kVcExtensionUnit = 0x06;
constexpr std::size_t kXuGuidOffset = 4;

// The unit and selector are in the id, so that a listed control is all setXuControl() needs.
std::uint32_t idOf(const ExtensionUnit& unit, std::uint8_t selector) {
    return kXuIdBase | static_cast<std::uint32_t>(unit.id) << 8 | selector;
}

std::uint32_t idOf(const ExtensionUnit& unit, const XuControlSpec& spec) {
    return idOf(unit, spec.selector);
}

const XuControlSpec* specOf(std::uint32_t id) {
    const auto& specs = kRealsenseDepthXu.controls;
    const auto spec = std::find_if(specs.begin(), specs.end(),
                                   [id](const XuControlSpec& s) { return idOf(kRealsenseDepthXu, s) == id; });
    return spec == specs.end() ? nullptr : &*spec;
}

// One control of one unit on an open node: what each query is sent to.
struct XuTarget {
    Syscalls& sys;
    int fd;
    std::uint8_t unit;
    const XuControlSpec& spec;
};

int xuQuery(const XuTarget& t, std::uint8_t query, std::uint8_t* data, std::uint16_t size) {
    uvc_xu_control_query q{};
    q.unit = t.unit;
    q.selector = t.spec.selector;
    q.query = query;
    q.size = size;
    q.data = data;
    return xioctl(t.sys, t.fd, UVCIOC_CTRL_QUERY, &q);
}

// A control's bytes are little-endian, as every multi-byte USB field is (USB 2.0, 8.1), whatever the host's.
std::optional<std::int64_t> getValue(const XuTarget& t, std::uint8_t query) {
    std::array<std::uint8_t, 4> bytes{};
    if (t.spec.sizeBytes > bytes.size() || xuQuery(t, query, bytes.data(), t.spec.sizeBytes) < 0)
        return std::nullopt;
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < t.spec.sizeBytes; ++i)
        value |= static_cast<std::uint32_t>(bytes[i]) << (8 * i);
    return value;
}

// GET_INFO and GET_LEN say whether the camera has the control as we know it: readable, and of our size.
std::optional<std::uint8_t> infoOf(const XuTarget& t) {
    std::uint8_t info = 0;
    if (xuQuery(t, UVC_GET_INFO, &info, 1) < 0 || (info & UVC_CONTROL_CAP_GET) == 0)
        return std::nullopt;
    std::array<std::uint8_t, 2> length{};
    if (xuQuery(t, UVC_GET_LEN, length.data(), 2) < 0 || (length[0] | length[1] << 8) != t.spec.sizeBytes)
        return std::nullopt;
    return info;
}

std::optional<V4l2Control> describe(const XuTarget& t, std::uint32_t id) {
    const auto info = infoOf(t);
    if (!info)
        return std::nullopt;
    const auto minimum = getValue(t, UVC_GET_MIN);
    const auto maximum = getValue(t, UVC_GET_MAX);
    const auto resolution = getValue(t, UVC_GET_RES);
    const auto defaultValue = getValue(t, UVC_GET_DEF);
    const auto current = getValue(t, UVC_GET_CUR);
    if (!minimum || !maximum || !resolution || !defaultValue || !current || *minimum > *maximum)
        return std::nullopt;
    V4l2Control c;
    c.id = id;
    c.name = t.spec.name;
    c.type = t.spec.type;
    c.minimum = *minimum;
    c.maximum = *maximum;
    c.step = static_cast<std::uint64_t>(std::max<std::int64_t>(*resolution, 1));
    c.defaultValue = *defaultValue;
    c.flags = (*info & UVC_CONTROL_CAP_SET) ? 0 : V4L2_CTRL_FLAG_READ_ONLY;
    c.value = *current;
    const auto& labels = t.spec.menuLabels;
    for (std::int64_t i = c.minimum; t.spec.type == V4L2_CTRL_TYPE_MENU && i <= c.maximum; ++i)
        c.menu.push_back(
            {i, i < std::ssize(labels) ? labels[static_cast<std::size_t>(i)] : std::to_string(i)});
    return c;
}

// Flags each listed control whose auto control is listed and on. An auto control that could not be read
// leaves its partner active: nothing says the camera ignores it.
void markDecidedByAuto(const ExtensionUnit& unit, std::vector<V4l2Control>& controls) {
    for (const XuControlSpec& spec : unit.controls) {
        const auto find = [&](std::uint8_t selector) {
            return std::find_if(controls.begin(), controls.end(),
                                [&](const V4l2Control& c) { return c.id == idOf(unit, selector); });
        };
        const auto manual = find(spec.selector);
        const auto automatic = spec.autoSelector ? find(spec.autoSelector) : controls.end();
        if (manual != controls.end() && automatic != controls.end() && automatic->value.value_or(0) != 0)
            manual->flags |= V4L2_CTRL_FLAG_INACTIVE;
    }
}

} // namespace

XuAccess xuAccessFor(std::uint16_t vendorId, std::uint16_t productId, const std::string& depthNodePath) {
    const usb::KnownCamera* camera = usb::findKnownCamera(vendorId, productId);
    if (!camera || !camera->realsenseDepthXu)
        return {};
    return {depthNodePath, &kRealsenseDepthXu};
}

bool declaresExtensionUnit(std::span<const std::uint8_t> descriptors, const ExtensionUnit& unit) {
    bool videoControl = false;
    // Each descriptor starts with its length and type; a length that overruns the rest ends the walk.
    for (std::size_t at = 0; at + 2 <= descriptors.size();) {
        const std::size_t length = descriptors[at];
        if (length < 2 || length > descriptors.size() - at)
            return false;
        const std::span<const std::uint8_t> d = descriptors.subspan(at, length);
        if (d[1] == kInterface && d.size() >= 7)
            videoControl = d[5] == kVideoClass && d[6] == kVideoControlSubclass;
        const bool extensionUnit = videoControl && d[1] == kCsInterface && d.size() >= kXuGuidOffset + 16 &&
                                   d[2] == kVcExtensionUnit && d[3] == unit.id;
        if (extensionUnit && std::equal(unit.guid.begin(), unit.guid.end(), d.begin() + kXuGuidOffset))
            return true;
        at += length;
    }
    return false;
}

bool isXuControl(std::uint32_t id) {
    return (id & kXuIdMask) == kXuIdBase;
}

std::vector<V4l2Control> queryXuControls(Syscalls& sys, int fd, const XuAccess& access) {
    std::vector<V4l2Control> controls;
    if (!access.unit)
        return controls;
    for (const XuControlSpec& spec : access.unit->controls)
        if (auto c = describe({sys, fd, access.unit->id, spec}, idOf(*access.unit, spec)))
            controls.push_back(std::move(*c));
    markDecidedByAuto(*access.unit, controls);
    return controls;
}

Status setXuControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                    std::int64_t value) {
    const std::string what = "'" + controlKey(control.name) + "'";
    const XuControlSpec* spec = specOf(control.id);
    if (!spec)
        return Error{path + ": " + what + " is no extension-unit control of a known camera"};
    if (Status s = checkControlValue(control, value); !s)
        return Error{path + ": " + s.error().message};
    std::array<std::uint8_t, 4> bytes{};
    for (std::size_t i = 0; i < spec->sizeBytes; ++i)
        bytes[i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i));
    const XuTarget target{sys, fd, kRealsenseDepthXu.id, *spec};
    const std::string setting = path + ": cannot set " + what + " to " + std::to_string(value) + ": ";
    if (const int r = xuQuery(target, UVC_SET_CUR, bytes.data(), spec->sizeBytes); r < 0)
        return Error{setting + std::strerror(-r)};
    const auto now = getValue(target, UVC_GET_CUR);
    if (!now)
        return Error{setting + "the camera took it but cannot be read back"};
    if (*now != value)
        return Error{setting + "the camera keeps " + std::to_string(*now)};
    return Status::success();
}

Expected<std::vector<V4l2Control>> queryNodeControls(Syscalls& sys, int fd, const std::string& path,
                                                     const XuAccess& access) {
    auto controls = queryControls(sys, fd, path);
    if (!controls || !access.reaches(path))
        return controls;
    for (V4l2Control& xu : queryXuControls(sys, fd, access)) {
        // A driver that maps the XU to a V4L2 control of the same name already shows it.
        const bool mapped = std::any_of(controls->begin(), controls->end(), [&xu](const V4l2Control& c) {
            return controlKey(c.name) == controlKey(xu.name);
        });
        if (!mapped)
            controls->push_back(std::move(xu));
    }
    return controls;
}

Status setNodeControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                      std::int64_t value) {
    if (isXuControl(control.id))
        return setXuControl(sys, fd, path, control, value);
    return setControl(sys, fd, path, control, value);
}

} // namespace dc::devices::v4l2
