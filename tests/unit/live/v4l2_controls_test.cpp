// What `depthcloud controls` makes of control names and values before any ioctl: v4l2-ctl's names, values
// read as each type reads them, and a value outside what a control takes refused naming both. The
// controls of a real driver are read and set in the kernel tier (vivid).

#include "devices/uvc/v4l2/control_preset.h"
#include "devices/uvc/v4l2/controls.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <limits>

namespace dc::devices::v4l2 {
namespace {

V4l2Control integer(std::int64_t min, std::int64_t max, std::uint64_t step) {
    V4l2Control c;
    c.name = "Gain";
    c.type = V4L2_CTRL_TYPE_INTEGER;
    c.minimum = min;
    c.maximum = max;
    c.step = step;
    return c;
}

TEST(V4l2Controls, KeysAreV4l2CtlsNames) {
    EXPECT_EQ(controlKey("White Balance, Automatic"), "white_balance_automatic");
    EXPECT_EQ(controlKey("Brightness"), "brightness");
    EXPECT_EQ(controlKey("  Exposure (Absolute) "), "exposure_absolute");
    EXPECT_EQ(controlKey("Integer 32 Bits"), "integer_32_bits");
    EXPECT_EQ(controlKey("---"), "");
}

TEST(V4l2Controls, ValuesAreReadAsTheirTypeReadsThem) {
    EXPECT_EQ(*parseControlValue(integer(0, 255, 1), "200"), 200);
    EXPECT_EQ(*parseControlValue(integer(0, 255, 1), "0x10"), 16);
    EXPECT_EQ(*parseControlValue(integer(-10, 10, 1), "-3"), -3);
    EXPECT_FALSE(parseControlValue(integer(0, 255, 1), "bright").ok());
    EXPECT_FALSE(parseControlValue(integer(0, 255, 1), "12x").ok());
    V4l2Control boolean = integer(0, 1, 1);
    boolean.type = V4L2_CTRL_TYPE_BOOLEAN;
    EXPECT_EQ(*parseControlValue(boolean, "on"), 1);
    EXPECT_EQ(*parseControlValue(boolean, "FALSE"), 0);
    V4l2Control menu = integer(0, 3, 1);
    menu.type = V4L2_CTRL_TYPE_MENU;
    menu.menu = {{0, "Manual Mode"}, {1, "Auto Mode"}, {3, "Aperture Priority Mode"}};
    EXPECT_EQ(*parseControlValue(menu, "aperture priority mode"), 3);
    EXPECT_EQ(*parseControlValue(menu, "1"), 1);
    const auto bad = parseControlValue(menu, "Shutter Priority Mode");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("'gain'"), std::string::npos) << bad.error().message;
}

TEST(V4l2Controls, AValueOutsideWhatTheControlTakesIsRefusedNamingBoth) {
    const V4l2Control c = integer(0, 100, 5);
    EXPECT_TRUE(checkControlValue(c, 0).ok());
    EXPECT_TRUE(checkControlValue(c, 100).ok());
    EXPECT_TRUE(checkControlValue(c, 35).ok());
    const Status high = checkControlValue(c, 101);
    ASSERT_FALSE(high.ok());
    EXPECT_EQ(high.error().message, "'gain' takes 0..100, not 101");
    const Status off = checkControlValue(c, 37);
    ASSERT_FALSE(off.ok());
    EXPECT_EQ(off.error().message, "'gain' takes 0..100 in steps of 5, not 37");
    V4l2Control menu = integer(0, 3, 1);
    menu.type = V4L2_CTRL_TYPE_MENU;
    menu.menu = {{0, "a"}, {1, "b"}, {3, "d"}};
    EXPECT_FALSE(checkControlValue(menu, 2).ok()) << "2 is inside the range but no entry of the menu";
    V4l2Control readOnly = integer(0, 100, 1);
    readOnly.flags = V4L2_CTRL_FLAG_READ_ONLY;
    EXPECT_EQ(checkControlValue(readOnly, 5).error().message, "'gain' is read-only");
    V4l2Control text = integer(0, 32, 1);
    text.type = V4L2_CTRL_TYPE_STRING;
    EXPECT_FALSE(checkControlValue(text, 1).ok());
    V4l2Control extremes =
        integer(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max(), 1);
    extremes.type = V4L2_CTRL_TYPE_INTEGER64;
    EXPECT_TRUE(checkControlValue(extremes, std::numeric_limits<std::int64_t>::min()).ok());
    EXPECT_TRUE(checkControlValue(extremes, std::numeric_limits<std::int64_t>::max()).ok());
}

V4l2Control named(const char* name, std::uint32_t type, std::int64_t value, std::uint32_t flags = 0) {
    V4l2Control c = integer(0, 255, 1);
    c.name = name;
    c.type = type;
    c.value = value;
    c.flags = flags;
    return c;
}

// A preset keeps what a person chose and nothing the driver decides: no read-only, inactive or volatile
// value, no button or class; menus by their label so that the file reads as the window does.
TEST(ControlPresets, KeepTheValuesAPersonChoseInTheDriversOrder) {
    V4l2Control menu = named("Auto Exposure", V4L2_CTRL_TYPE_MENU, 1);
    menu.menu = {{0, "Manual Mode"}, {1, "Aperture Priority Mode"}};
    V4l2Control writeOnly = named("Pan, Relative", V4L2_CTRL_TYPE_INTEGER, 0);
    writeOnly.value.reset();
    const std::vector<V4l2Control> controls{
        named("User Controls", V4L2_CTRL_TYPE_CTRL_CLASS, 0),
        named("Brightness", V4L2_CTRL_TYPE_INTEGER, 200),
        menu,
        named("Exposure Time, Absolute", V4L2_CTRL_TYPE_INTEGER, 156, V4L2_CTRL_FLAG_INACTIVE),
        named("Gain", V4L2_CTRL_TYPE_INTEGER, 12, V4L2_CTRL_FLAG_VOLATILE),
        named("Frame Counter", V4L2_CTRL_TYPE_INTEGER, 9, V4L2_CTRL_FLAG_READ_ONLY),
        named("Button", V4L2_CTRL_TYPE_BUTTON, 0),
        writeOnly,
        named("Emitter Enabled", V4L2_CTRL_TYPE_BOOLEAN, 1),
        named("Big", V4L2_CTRL_TYPE_INTEGER64, -5000000000),
    };
    const PresetNode node = presetNodeOf("cam", controls);
    const std::vector<std::pair<std::string, std::string>> expected{
        {"brightness", "200"},
        {"auto_exposure", "Aperture Priority Mode"},
        {"emitter_enabled", "1"},
        {"big", "-5000000000"}};
    EXPECT_EQ(node.values, expected);
    const ControlPreset preset{"usb:8086:0b07", {node, {"other", {}}}};
    const auto back = parsePreset(presetJson(preset), "p.json");
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->camera, preset.camera);
    ASSERT_EQ(back->nodes.size(), 2u);
    EXPECT_EQ(back->nodes[0].card, "cam");
    EXPECT_EQ(back->nodes[0].values, expected) << "the order survives the file";
    EXPECT_TRUE(back->nodes[1].values.empty());
}

TEST(ControlPresets, AFileThatIsNoPresetIsRefusedSayingWhere) {
    const auto error = [](std::string_view json) {
        const auto p = parsePreset(json, "p.json");
        return p ? std::string("accepted") : p.error().message;
    };
    EXPECT_EQ(error("{"), "p.json: not JSON");
    EXPECT_EQ(error(R"({"nodes": []})"),
              "p.json: not a depthcloud controls preset (no \"format\": \"depthcloud-controls-preset\")");
    EXPECT_EQ(error(R"({"format": "depthcloud-controls-preset", "version": 2, "nodes": []})"),
              "p.json: preset version 2 is newer than this depthcloud's 1");
    EXPECT_EQ(error(R"({"format": "depthcloud-controls-preset", "version": 1})"),
              "p.json: expected a \"nodes\" array");
    EXPECT_EQ(
        error(
            R"({"format": "depthcloud-controls-preset", "version": 1, "nodes": [{"controls": [{"name": "gain"}]}]})"),
        "p.json: nodes[0].controls[0]: expected {\"name\": TEXT, \"value\": NUMBER or TEXT}");
    EXPECT_EQ(
        error(
            R"({"format": "depthcloud-controls-preset", "version": 1, "nodes": [{"controls": [{"name": "gain", "value": true}]}]})"),
        "p.json: nodes[0].controls[0]: the value of 'gain' must be an integer or a menu entry's label");
}

} // namespace
} // namespace dc::devices::v4l2
