#pragma once

#include "base/expected.h"
#include "devices/uvc/v4l2/syscalls.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dc::devices::v4l2 {

// One entry of a menu or integer-menu control: its index and its label (an integer menu's value, written
// out).
struct MenuEntry {
    std::int64_t index = 0;
    std::string label;
};

// One control of a V4L2 node as VIDIOC_QUERY_EXT_CTRL describes it, with its current value where it has
// one that can be read as an integer.
struct V4l2Control {
    std::uint32_t id = 0;
    std::string name;
    std::uint32_t type = 0; // V4L2_CTRL_TYPE_*
    std::int64_t minimum = 0;
    std::int64_t maximum = 0;
    std::uint64_t step = 0;
    std::int64_t defaultValue = 0;
    std::uint32_t flags = 0; // V4L2_CTRL_FLAG_*
    std::vector<MenuEntry> menu;
    // Unset for control classes, buttons, write-only and compound controls, and a value the driver would
    // not give (reading it failed).
    std::optional<std::int64_t> value;

    bool isClass() const;
    bool readOnly() const;
    bool inactive() const;
    // Holds an integer, boolean, menu, bitmask or button: what setControl() can set.
    bool settable() const;
};

// v4l2-ctl's name for a control ("White Balance, Automatic" -> "white_balance_automatic"): lower case,
// each run of other characters one underscore, none at either end.
std::string controlKey(std::string_view name);
// The flags a person cares about, by name: "read-only", "inactive", "grabbed", "volatile", "write-only".
std::vector<std::string> controlFlagNames(const V4l2Control& control);
// "int", "bool", "menu", "intmenu", "button", "int64", "bitmask", "class", "string" or "compound".
const char* controlTypeName(std::uint32_t type);

// Every control of the node at `fd` in the driver's order, control classes included, disabled ones left
// out. `path` names the node in errors.
Expected<std::vector<V4l2Control>> queryControls(Syscalls& sys, int fd, const std::string& path);

// Whether `value` is one `control` takes: within its range and on its step, one of its menu's entries,
// and not read-only. The error names the control, the value and what it takes.
Status checkControlValue(const V4l2Control& control, std::int64_t value);
// Reads `text` as a value of `control`: an integer (decimal or 0x hex), for a boolean also true/false/on/
// off, for a menu also an entry's label (any case).
Expected<std::int64_t> parseControlValue(const V4l2Control& control, std::string_view text);
// Sets the control (after checkControlValue) with VIDIOC_S_EXT_CTRLS; the error names the node, the
// control, the value and why the driver refused it (EBUSY, EACCES, ERANGE, EINVAL ...).
Status setControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                  std::int64_t value);

} // namespace dc::devices::v4l2
