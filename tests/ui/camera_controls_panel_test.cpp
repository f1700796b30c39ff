// The Camera controls panel as a person uses it: a click on a widget sets that control, an auto control
// greys its manual partner until it is switched off, "Reset to defaults" sets back what changed, and a
// value the camera refuses is said. The camera is an in-memory one at Device::sensorControls(); the same
// surface over a real driver (vivid) is tested in the kernel tier.

#include "panel_fixture.h"
#include "ui/panels.h"

#include <tuple>

namespace dc::ui::test {
namespace {

using devices::SensorControl;

constexpr const char* kPath = "/dev/video9";
constexpr std::uint32_t kBrightness = 1, kAutoGain = 2, kGain = 3;

SensorControl control(std::uint32_t id, const char* name, SensorControl::Kind kind, std::int64_t value,
                      std::int64_t defaultValue) {
    SensorControl c;
    c.id = id;
    c.name = name;
    c.kind = kind;
    c.minimum = 0;
    c.maximum = kind == SensorControl::Kind::Boolean ? 1 : 255;
    c.value = value;
    c.defaultValue = defaultValue;
    return c;
}

// A camera whose automatic gain decides its gain, as vivid's and most UVC cameras' do.
class MemoryCamera final : public devices::SensorControls {
public:
    MemoryCamera() {
        SensorControl heading;
        heading.name = "User Controls";
        heading.kind = SensorControl::Kind::Heading;
        SensorControl gain = control(kGain, "Gain", SensorControl::Kind::Integer, 10, 100);
        gain.inactive = true;
        node_ = {kPath,
                 "Test camera",
                 {heading, control(kBrightness, "Brightness", SensorControl::Kind::Integer, 200, 128),
                  control(kAutoGain, "Gain, Automatic", SensorControl::Kind::Boolean, 1, 1), gain}};
    }

    Expected<std::vector<devices::SensorControlNode>> read() override { return std::vector{node_}; }
    std::vector<devices::StreamMode> depthModes() override {
        return {{"Z16", 640, 480, 30}, {"Z16", 848, 480, 15}};
    }
    std::vector<devices::StreamMode> colorModes() override {
        return {{"YUYV", 640, 480, 30}, {"MJPG", 1280, 720, 15}};
    }
    Status set(const std::string& path, std::uint32_t id, std::int64_t value) override {
        sets.emplace_back(path, id, value);
        if (id == refuse)
            return Error{path + ": cannot set 'brightness' to " + std::to_string(value) +
                         ": Device or resource busy"};
        for (SensorControl& c : node_.controls)
            if (c.id == id)
                c.value = value;
        node_.controls[3].inactive = *node_.controls[2].value == 1;
        return {};
    }

    std::vector<std::tuple<std::string, std::uint32_t, std::int64_t>> sets;
    std::uint32_t refuse = 0;

private:
    devices::SensorControlNode node_;
};

class CameraControlsPanelTest : public PanelTest {
protected:
    void SetUp() override {
        PanelTest::SetUp();
        state_.controls = camera_;
        draw_ = [this] {
            ImGui::SetNextWindowPos(ImVec2(20, 20));
            ImGui::SetNextWindowSize(ImVec2(460, 400));
            drawCameraControlsPanel(state_, time_, &open_);
            time_ += 1.0 / 60.0;
        };
        frame();
    }

    void clickWidget(const std::string& label) {
        const auto at = locate(kCameraControlsTitle, label.c_str());
        ASSERT_TRUE(at) << label << " is not drawn";
        click(*at);
    }

    std::shared_ptr<MemoryCamera> camera_ = std::make_shared<MemoryCamera>();
    CameraControlsState state_;
    double time_ = 0.0;
    bool open_ = true;
};

TEST_F(CameraControlsPanelTest, AnAutoControlGreysItsPartnerUntilItIsSwitchedOff) {
    const std::string gain = std::string("Gain##") + kPath + ":" + std::to_string(kGain);
    clickWidget(gain);
    EXPECT_TRUE(camera_->sets.empty()) << "the gain is inactive while automatic gain is on";

    clickWidget(std::string("Gain, Automatic##") + kPath + ":" + std::to_string(kAutoGain));
    ASSERT_EQ(camera_->sets.size(), 1u);
    EXPECT_EQ(camera_->sets[0], std::make_tuple(std::string(kPath), kAutoGain, std::int64_t{0}));
    frame();
    ASSERT_EQ(state_.nodes.size(), 1u);
    EXPECT_FALSE(state_.nodes[0].controls[3].inactive) << "read back at once after the change";

    clickWidget(gain);
    ASSERT_EQ(camera_->sets.size(), 2u) << "now the gain takes a click";
    EXPECT_EQ(std::get<1>(camera_->sets[1]), kGain);
}

TEST_F(CameraControlsPanelTest, ResetToDefaultsSetsBackWhatChangedAndSaysWhatTheCameraRefused) {
    camera_->refuse = kBrightness;
    clickWidget(std::string("Reset to defaults##") + kPath + ":0");
    ASSERT_EQ(camera_->sets.size(), 1u) << "only brightness differs from its default; gain is inactive";
    EXPECT_EQ(camera_->sets[0], std::make_tuple(std::string(kPath), kBrightness, std::int64_t{128}));
    const std::string refusal =
        std::string(kPath) + ": cannot set 'brightness' to 128: Device or resource busy";
    EXPECT_EQ(state_.message, refusal) << "shown in the panel";
    EXPECT_EQ(state_.refused, std::vector<std::string>{refusal}) << "and handed to the log";

    camera_->refuse = 0;
    clickWidget(std::string("Reset to defaults##") + kPath + ":0");
    EXPECT_EQ(std::get<2>(camera_->sets.back()), 128);
    EXPECT_TRUE(state_.message.empty()) << "a value set clears the refusal";
}

TEST_F(CameraControlsPanelTest, ADepthModeChosenFromTheListIsHandedToTheViewer) {
    clickWidget("Depth mode");
    const auto entry = locate("##Combo_00", "848x480 @ 15 Hz Z16");
    ASSERT_TRUE(entry) << "the depth node's modes are listed";
    click(*entry);
    ASSERT_TRUE(state_.chosenMode);
    EXPECT_EQ(*state_.chosenMode, (devices::StreamMode{"Z16", 848, 480, 15}));
    EXPECT_EQ(state_.modeShown, "848x480 @ 15 Hz Z16");
}

TEST_F(CameraControlsPanelTest, AColourModeChosenFromItsOwnListIsHandedToTheViewer) {
    clickWidget("Colour mode");
    ASSERT_FALSE(locate("##Combo_00", "848x480 @ 15 Hz Z16")) << "the colour list holds no depth mode";
    const auto entry = locate("##Combo_00", "1280x720 @ 15 Hz MJPG");
    ASSERT_TRUE(entry) << "the colour node's modes are listed";
    click(*entry);
    ASSERT_TRUE(state_.chosenColorMode);
    EXPECT_EQ(*state_.chosenColorMode, (devices::StreamMode{"MJPG", 1280, 720, 15}));
    EXPECT_EQ(state_.colorModeShown, "1280x720 @ 15 Hz MJPG");
    EXPECT_FALSE(state_.chosenMode) << "the depth mode is left as it was";
    EXPECT_TRUE(state_.modeShown.empty());
}

TEST_F(CameraControlsPanelTest, ASourceWithoutControlsSaysSo) {
    state_ = {};
    frame();
    frame();
    EXPECT_TRUE(state_.nodes.empty());
    EXPECT_NE(ImGui::FindWindowByName(kCameraControlsTitle), nullptr);
}

} // namespace
} // namespace dc::ui::test
