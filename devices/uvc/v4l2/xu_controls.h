#pragma once

#include "base/expected.h"
#include "devices/uvc/v4l2/controls.h"
#include "devices/uvc/v4l2/syscalls.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dc::devices::v4l2 {

// One control of a UVC extension unit (XU) that we know the meaning of: uvcvideo maps no V4L2 control to a
// vendor's XU, so these are reached with UVCIOC_CTRL_QUERY and shown as V4L2 controls of the node.
struct XuControlSpec {
    const char* name = ""; // shown as the driver's names are; presets keep it by its controlKey()
    std::uint8_t selector = 0;
    std::uint16_t sizeBytes = 0; // what GET_LEN must answer; a camera answering otherwise is not trusted
    std::uint32_t type = 0;      // V4L2_CTRL_TYPE_INTEGER, _BOOLEAN or _MENU
    std::span<const char* const> menuLabels = {}; // a menu's labels by value
    // The selector of the unit's auto control that decides this one while it is on (0: none): listed
    // inactive then, as V4L2 lists exposure_time_absolute while auto_exposure is not manual.
    std::uint8_t autoSelector = 0;
};

// One vendor's extension unit: its id among the camera's units, its GUID as the USB descriptors carry it
// (the first three fields little-endian), and the controls we know of it.
struct ExtensionUnit {
    std::uint8_t id = 0;
    std::array<std::uint8_t, 16> guid{};
    std::span<const XuControlSpec> controls;
};

// A camera's extension unit and the node that reaches it. None (a null unit) for any camera the
// known-camera table does not mark as having one: an XU request means something else, or something
// harmful, to another vendor's firmware, so none is ever sent there.
struct XuAccess {
    std::string nodePath;
    const ExtensionUnit* unit = nullptr;

    bool reaches(const std::string& path) const { return unit != nullptr && path == nodePath; }
};

// The extension unit the known-camera table gives VID:PID, reached through `depthNodePath`.
XuAccess xuAccessFor(std::uint16_t vendorId, std::uint16_t productId, const std::string& depthNodePath);

// Whether a USB device's descriptors (sysfs's "descriptors": the device descriptor, then the active
// configuration's) declare `unit`: an extension unit of its id and GUID. A device that borrows a known
// camera's VID:PID (a UVC gadget) does not.
bool declaresExtensionUnit(std::span<const std::uint8_t> descriptors, const ExtensionUnit& unit);

// Whether a control id is one of ours for an XU control rather than the driver's.
bool isXuControl(std::uint32_t id);

// Each control of `access`'s unit that answers GET_INFO, GET_LEN, GET_MIN, GET_MAX, GET_RES, GET_DEF and
// GET_CUR on `fd`, as a control of the node; one that fails a query, or answers a size other than its own,
// is left out. Read-only when GET_INFO does not offer SET_CUR; inactive while its auto control is listed
// and on.
std::vector<V4l2Control> queryXuControls(Syscalls& sys, int fd, const XuAccess& access);

// Sets an XU control (after checkControlValue) with SET_CUR and reads it back with GET_CUR: the error
// names the node, the control and the value, and says when the camera kept another value.
Status setXuControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                    std::int64_t value);

// The node's V4L2 controls followed by its XU controls where `access` reaches the node.
Expected<std::vector<V4l2Control>> queryNodeControls(Syscalls& sys, int fd, const std::string& path,
                                                     const XuAccess& access);
// setControl() or setXuControl(), by the control's id.
Status setNodeControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                      std::int64_t value);

} // namespace dc::devices::v4l2
