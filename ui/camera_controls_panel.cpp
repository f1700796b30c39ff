// The Camera controls panel: every control of each node of a live camera, with the widget its type takes,
// set as it changes and read back from the driver. Read again every second as well, so that a change made
// by another program (v4l2-ctl) or by the driver itself (an auto control) shows.

#include "ui/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dc::ui {

namespace {

using devices::SensorControl;

constexpr double kReadInterval = 1.0;

// One widget label per control, unique in the panel: the same control name appears on several nodes.
std::string labelOf(const std::string& text, const std::string& path, std::uint32_t id) {
    return text + "##" + path + ":" + std::to_string(id);
}

std::string menuLabel(const SensorControl& c, std::int64_t value) {
    for (const auto& [index, label] : c.menu)
        if (index == value)
            return label;
    return std::to_string(value);
}

// The control's widget; the value a person chose, if they changed it this frame.
std::optional<std::int64_t> controlWidget(const SensorControl& c, const std::string& path) {
    const std::string label = labelOf(c.name, path, c.id);
    std::int64_t value = c.value.value_or(c.defaultValue);
    switch (c.kind) {
    case SensorControl::Kind::Integer:
        if (ImGui::SliderScalar(label.c_str(), ImGuiDataType_S64, &value, &c.minimum, &c.maximum)) {
            // A slider moves by pixels; the driver takes values on the control's step only.
            const std::int64_t step = std::max<std::int64_t>(c.step, 1);
            return c.minimum + (value - c.minimum + step / 2) / step * step;
        }
        return std::nullopt;
    case SensorControl::Kind::Boolean: {
        bool on = value != 0;
        return ImGui::Checkbox(label.c_str(), &on) ? std::optional<std::int64_t>(on ? 1 : 0) : std::nullopt;
    }
    case SensorControl::Kind::Menu: {
        std::optional<std::int64_t> chosen;
        if (ImGui::BeginCombo(label.c_str(), menuLabel(c, value).c_str())) {
            for (const auto& [index, entry] : c.menu)
                if (ImGui::Selectable(labelOf(entry, path, c.id).c_str(), index == value))
                    chosen = index;
            ImGui::EndCombo();
        }
        return chosen;
    }
    case SensorControl::Kind::Button:
        return ImGui::Button(label.c_str()) ? std::optional<std::int64_t>(0) : std::nullopt;
    case SensorControl::Kind::Heading:
    case SensorControl::Kind::Other:
        break;
    }
    ImGui::TextDisabled("%s (not settable here)", c.name.c_str());
    return std::nullopt;
}

bool settableToDefault(const SensorControl& c) {
    return c.value && !c.readOnly && !c.inactive &&
           (c.kind == SensorControl::Kind::Integer || c.kind == SensorControl::Kind::Boolean ||
            c.kind == SensorControl::Kind::Menu);
}

// Sets one control and keeps the driver's answer; a refusal is shown in the panel and returned for the log.
void apply(CameraControlsState& state, const std::string& path, std::uint32_t id, std::int64_t value) {
    if (Status s = state.controls->set(path, id, value); !s) {
        state.message = s.error().message;
        state.refused.push_back(s.error().message);
    } else {
        state.message.clear();
    }
    state.readAtSeconds = -kReadInterval; // read back at once
}

void drawNode(CameraControlsState& state, const devices::SensorControlNode& node) {
    const std::string header = labelOf(node.card + "  " + node.path, node.path, 0);
    if (!ImGui::CollapsingHeader(header.c_str(), ImGuiTreeNodeFlags_DefaultOpen))
        return;
    if (ImGui::Button(labelOf("Reset to defaults", node.path, 0).c_str()))
        for (const SensorControl& c : node.controls)
            if (settableToDefault(c) && *c.value != c.defaultValue)
                apply(state, node.path, c.id, c.defaultValue);
    for (const SensorControl& c : node.controls) {
        if (c.kind == SensorControl::Kind::Heading) {
            ImGui::Separator();
            ImGui::TextDisabled("%s", c.name.c_str());
            continue;
        }
        ImGui::BeginDisabled(c.readOnly || c.inactive);
        const auto chosen = controlWidget(c, node.path);
        ImGui::EndDisabled();
        if (c.inactive && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("inactive: an automatic control decides it now");
        if (chosen)
            apply(state, node.path, c.id, *chosen);
    }
}

std::string modeText(const devices::StreamMode& m) {
    char text[64];
    std::snprintf(text, sizeof text, "%dx%d @ %g Hz %s", m.width, m.height, m.fps, m.format.c_str());
    return text;
}

// One node's mode list; a mode picked is left in `chosen` and shown as current from then on.
void drawModeList(const char* label, const std::vector<devices::StreamMode>& modes,
                  std::optional<devices::StreamMode>& chosen, std::string& shown) {
    if (modes.empty())
        return;
    if (ImGui::BeginCombo(label, shown.empty() ? "as opened" : shown.c_str())) {
        for (const devices::StreamMode& m : modes)
            if (ImGui::Selectable(modeText(m).c_str(), modeText(m) == shown)) {
                chosen = m;
                shown = modeText(m);
            }
        ImGui::EndCombo();
    }
}

void drawModes(CameraControlsState& state) {
    if (!state.modes)
        state.modes = state.controls->depthModes();
    if (!state.colorModes)
        state.colorModes = state.controls->colorModes();
    drawModeList("Depth mode", *state.modes, state.chosenMode, state.modeShown);
    drawModeList("Colour mode", *state.colorModes, state.chosenColorMode, state.colorModeShown);
}

} // namespace

void drawCameraControlsPanel(CameraControlsState& state, double nowSeconds, bool* open) {
    if (!ImGui::Begin(kCameraControlsTitle, open)) {
        ImGui::End();
        return;
    }
    if (!state.controls) {
        ImGui::TextWrapped("This source has no controls: live V4L2 and USB cameras have.");
        ImGui::End();
        return;
    }
    // changed() is asked every frame, so that it keeps watching and its events do not pile up.
    if (state.controls->changed() || nowSeconds - state.readAtSeconds >= kReadInterval) {
        auto nodes = state.controls->read();
        if (nodes)
            state.nodes = std::move(*nodes);
        else
            state.message = nodes.error().message;
        state.readAtSeconds = nowSeconds;
    }
    drawModes(state);
    if (!state.message.empty())
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", state.message.c_str());
    for (const devices::SensorControlNode& node : state.nodes)
        drawNode(state, node);
    ImGui::End();
}

} // namespace dc::ui
