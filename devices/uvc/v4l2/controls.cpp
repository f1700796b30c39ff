#include "devices/uvc/v4l2/controls.h"

#include <linux/videodev2.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <utility>

namespace dc::devices::v4l2 {

namespace {

constexpr std::uint32_t kNextControl = V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;

bool isMenu(std::uint32_t type) {
    return type == V4L2_CTRL_TYPE_MENU || type == V4L2_CTRL_TYPE_INTEGER_MENU;
}

bool holdsInteger(std::uint32_t type) {
    switch (type) {
    case V4L2_CTRL_TYPE_INTEGER:
    case V4L2_CTRL_TYPE_BOOLEAN:
    case V4L2_CTRL_TYPE_MENU:
    case V4L2_CTRL_TYPE_INTEGER_MENU:
    case V4L2_CTRL_TYPE_BITMASK:
    case V4L2_CTRL_TYPE_INTEGER64:
        return true;
    default:
        return false;
    }
}

std::string fixedString(const char* text, std::size_t size) {
    return {text, strnlen(text, size)};
}

// The entries of a menu control; indexes the driver skips (EINVAL) are not entries.
std::vector<MenuEntry> menuOf(Syscalls& sys, int fd, const V4l2Control& control) {
    std::vector<MenuEntry> entries;
    for (std::int64_t i = control.minimum; i <= control.maximum && i >= 0; ++i) {
        v4l2_querymenu m{};
        m.id = control.id;
        m.index = static_cast<std::uint32_t>(i);
        if (xioctl(sys, fd, VIDIOC_QUERYMENU, &m) < 0)
            continue;
        entries.push_back({i, control.type == V4L2_CTRL_TYPE_MENU
                                  ? fixedString(reinterpret_cast<const char*>(m.name), sizeof m.name)
                                  : std::to_string(m.value)});
    }
    return entries;
}

std::optional<std::int64_t> currentValue(Syscalls& sys, int fd, const V4l2Control& control) {
    if (!holdsInteger(control.type) || (control.flags & V4L2_CTRL_FLAG_WRITE_ONLY))
        return std::nullopt;
    v4l2_ext_control c{};
    c.id = control.id;
    v4l2_ext_controls list{};
    list.which = V4L2_CTRL_WHICH_CUR_VAL;
    list.count = 1;
    list.controls = &c;
    if (xioctl(sys, fd, VIDIOC_G_EXT_CTRLS, &list) < 0)
        return std::nullopt;
    if (control.type == V4L2_CTRL_TYPE_INTEGER64)
        return std::int64_t{c.value64};
    // A bitmask's 32 bits are unsigned, as its range is; read as signed, its top bit made it negative.
    if (control.type == V4L2_CTRL_TYPE_BITMASK)
        return static_cast<std::uint32_t>(c.value);
    return std::int64_t{c.value};
}

V4l2Control describe(const v4l2_query_ext_ctrl& q) {
    V4l2Control c;
    c.id = q.id;
    c.name = fixedString(q.name, sizeof q.name);
    c.type = q.type;
    c.minimum = q.minimum;
    c.maximum = q.maximum;
    c.step = q.step;
    c.defaultValue = q.default_value;
    c.flags = q.flags;
    return c;
}

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    return out;
}

std::optional<std::int64_t> integerOf(std::string_view text) {
    const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
    if (hex)
        text.remove_prefix(2);
    std::int64_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, hex ? 16 : 10);
    if (error != std::errc{} || end != text.data() + text.size() || text.empty())
        return std::nullopt;
    return value;
}

} // namespace

bool V4l2Control::isClass() const {
    return type == V4L2_CTRL_TYPE_CTRL_CLASS;
}

bool V4l2Control::readOnly() const {
    return (flags & V4L2_CTRL_FLAG_READ_ONLY) != 0;
}

bool V4l2Control::inactive() const {
    return (flags & V4L2_CTRL_FLAG_INACTIVE) != 0;
}

bool V4l2Control::settable() const {
    return holdsInteger(type) || type == V4L2_CTRL_TYPE_BUTTON;
}

std::string controlKey(std::string_view name) {
    std::string key;
    for (const char ch : name) {
        if (std::isalnum(static_cast<unsigned char>(ch)))
            key += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        else if (!key.empty() && key.back() != '_')
            key += '_';
    }
    while (!key.empty() && key.back() == '_')
        key.pop_back();
    return key;
}

std::vector<std::string> controlFlagNames(const V4l2Control& c) {
    constexpr std::pair<std::uint32_t, const char*> kNames[] = {{V4L2_CTRL_FLAG_READ_ONLY, "read-only"},
                                                                {V4L2_CTRL_FLAG_INACTIVE, "inactive"},
                                                                {V4L2_CTRL_FLAG_GRABBED, "grabbed"},
                                                                {V4L2_CTRL_FLAG_VOLATILE, "volatile"},
                                                                {V4L2_CTRL_FLAG_WRITE_ONLY, "write-only"}};
    std::vector<std::string> names;
    for (const auto& [flag, name] : kNames)
        if (c.flags & flag)
            names.emplace_back(name);
    return names;
}

const char* controlTypeName(std::uint32_t type) {
    switch (type) {
    case V4L2_CTRL_TYPE_INTEGER:
        return "int";
    case V4L2_CTRL_TYPE_BOOLEAN:
        return "bool";
    case V4L2_CTRL_TYPE_MENU:
        return "menu";
    case V4L2_CTRL_TYPE_INTEGER_MENU:
        return "intmenu";
    case V4L2_CTRL_TYPE_BUTTON:
        return "button";
    case V4L2_CTRL_TYPE_INTEGER64:
        return "int64";
    case V4L2_CTRL_TYPE_BITMASK:
        return "bitmask";
    case V4L2_CTRL_TYPE_CTRL_CLASS:
        return "class";
    case V4L2_CTRL_TYPE_STRING:
        return "string";
    default:
        return "compound";
    }
}

Expected<std::vector<V4l2Control>> queryControls(Syscalls& sys, int fd, const std::string& path) {
    std::vector<V4l2Control> controls;
    v4l2_query_ext_ctrl q{};
    q.id = kNextControl;
    int r = 0;
    while ((r = xioctl(sys, fd, VIDIOC_QUERY_EXT_CTRL, &q)) == 0) {
        V4l2Control c = describe(q);
        if (!(c.flags & V4L2_CTRL_FLAG_DISABLED)) {
            if (isMenu(c.type))
                c.menu = menuOf(sys, fd, c);
            c.value = currentValue(sys, fd, c);
            controls.push_back(std::move(c));
        }
        const std::uint32_t last = q.id;
        q = {};
        q.id = last | kNextControl;
    }
    // EINVAL: no control after the last one.
    if (r != -EINVAL)
        return Error{path + ": VIDIOC_QUERY_EXT_CTRL failed: " + std::strerror(-r)};
    return controls;
}

Status checkControlValue(const V4l2Control& c, std::int64_t value) {
    const std::string what = "'" + controlKey(c.name) + "' ";
    if (!c.settable())
        return Error{what + "is a " + controlTypeName(c.type) + " control, which cannot be set here"};
    if (c.readOnly())
        return Error{what + "is read-only"};
    if (c.type == V4L2_CTRL_TYPE_BUTTON)
        return Status::success();
    const std::string range = std::to_string(c.minimum) + ".." + std::to_string(c.maximum);
    if (value < c.minimum || value > c.maximum)
        return Error{what + "takes " + range + ", not " + std::to_string(value)};
    if (isMenu(c.type) &&
        std::none_of(c.menu.begin(), c.menu.end(), [&](const MenuEntry& e) { return e.index == value; }))
        return Error{what + "has no menu entry " + std::to_string(value)};
    if (c.type == V4L2_CTRL_TYPE_INTEGER && c.step > 1 &&
        static_cast<std::uint64_t>(value - c.minimum) % c.step != 0)
        return Error{what + "takes " + range + " in steps of " + std::to_string(c.step) + ", not " +
                     std::to_string(value)};
    return Status::success();
}

Expected<std::int64_t> parseControlValue(const V4l2Control& c, std::string_view text) {
    if (const auto value = integerOf(text))
        return *value;
    const std::string word = lower(text);
    if (c.type == V4L2_CTRL_TYPE_BOOLEAN && (word == "true" || word == "on"))
        return std::int64_t{1};
    if (c.type == V4L2_CTRL_TYPE_BOOLEAN && (word == "false" || word == "off"))
        return std::int64_t{0};
    for (const MenuEntry& e : c.menu)
        if (lower(e.label) == word)
            return e.index;
    return Error{"'" + controlKey(c.name) + "' takes a " + controlTypeName(c.type) + " value, not '" +
                 std::string(text) + "'"};
}

Status setControl(Syscalls& sys, int fd, const std::string& path, const V4l2Control& control,
                  std::int64_t value) {
    if (Status s = checkControlValue(control, value); !s)
        return s;
    v4l2_ext_control c{};
    c.id = control.id;
    if (control.type == V4L2_CTRL_TYPE_INTEGER64)
        c.value64 = value;
    else
        c.value = static_cast<std::int32_t>(value);
    v4l2_ext_controls list{};
    list.which = V4L2_CTRL_WHICH_CUR_VAL;
    list.count = 1;
    list.controls = &c;
    if (const int r = xioctl(sys, fd, VIDIOC_S_EXT_CTRLS, &list); r < 0)
        return Error{path + ": cannot set '" + controlKey(control.name) + "' to " + std::to_string(value) +
                     ": " + std::strerror(-r)};
    return Status::success();
}

} // namespace dc::devices::v4l2
