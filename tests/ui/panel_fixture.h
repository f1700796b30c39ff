#pragma once

// A fixture for one panel function drawn on its own, without a viewer: Debian's ImGui 1.86 with the OpenGL3
// renderer drawing into an offscreen target on Mesa llvmpipe, input injected as in ui_fixture.h.

#include "render/gl_context.h"
#include "ui/headless_ui.h"

#include <gtest/gtest.h>
#include <imgui_internal.h>

#include <functional>
#include <optional>

namespace dc::ui::test {

class PanelTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto ctx = render::EglContext::createHeadless();
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        context_.emplace(std::move(*ctx));
        ASSERT_TRUE(gui_.init(1280, 720).ok());
    }

    // One UI frame: `draw_` draws the panels under test with whatever input is set.
    void frame() {
        gui_.newFrame(1.0f / 60.0f);
        draw_();
        gui_.render();
    }

    void pressKey(ImGuiKey key) {
        const int index = ImGui::GetKeyIndex(key);
        gui_.io().KeysDown[index] = true;
        frame();
        gui_.io().KeysDown[index] = false;
        frame();
    }

    // Finds a widget by hovering candidate positions until ImGui reports its ID as hovered, as
    // UiTest::locate does.
    std::optional<ImVec2> locate(const char* window, const char* label) {
        ImGuiWindow* w = ImGui::FindWindowByName(window);
        if (!w)
            return std::nullopt;
        const ImGuiID id = w->GetID(label);
        for (float y = w->Pos.y; y < w->Pos.y + w->Size.y; y += 3.0f) {
            for (float x = w->Pos.x + 8.0f; x < w->Pos.x + w->Size.x; x += 12.0f) {
                gui_.io().MousePos = ImVec2(x, y);
                gui_.newFrame(1.0f / 60.0f);
                draw_();
                ImGui::EndFrame();
                if (ImGui::GetCurrentContext()->HoveredId == id)
                    return ImVec2(x, y);
            }
        }
        return std::nullopt;
    }

    // Presses the left button at `from`, moves to `to` over a few frames and releases it there.
    void drag(ImVec2 from, ImVec2 to) {
        gui_.io().MousePos = from;
        frame();
        gui_.io().MouseDown[0] = true;
        frame();
        for (int step = 1; step <= 4; ++step) {
            const float t = static_cast<float>(step) / 4.0f;
            gui_.io().MousePos = ImVec2(from.x + (to.x - from.x) * t, from.y + (to.y - from.y) * t);
            frame();
        }
        gui_.io().MouseDown[0] = false;
        frame();
    }

    void click(ImVec2 at) { drag(at, at); }

    std::optional<render::EglContext> context_;
    HeadlessUi gui_;
    std::function<void()> draw_ = [] {};
};

} // namespace dc::ui::test
