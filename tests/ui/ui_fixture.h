#pragma once

// The fixture of the headless UI tests: the real panel functions in Debian's ImGui 1.86 (IM_ASSERT live),
// drawn with the OpenGL3 renderer into an offscreen target on Mesa llvmpipe, driven by injected mouse and
// keyboard input; behind them the real engine (instrument, frame processor) and view renderer, put
// together as the tool does.

#include "devices/synthetic/synthetic_device.h"
#include "engine/instrument.h"
#include "render/gl_context.h"
#include "render/view_renderer.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <gtest/gtest.h>
#include <imgui_internal.h>

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace dc::ui::test {

inline devices::SyntheticConfig smallScene() {
    devices::SyntheticConfig c;
    c.cameraWidth = 640; // the image only colours points here; a small one keeps the suite fast
    c.cameraHeight = 480;
    c.fps = 120.0;
    return c;
}

class UiTest : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(initGl());
        ASSERT_NO_FATAL_FAILURE(startViewer(smallScene()));
    }

    void initGl(int width = 1280, int height = 720) {
        auto ctx = render::EglContext::createHeadless();
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        context_.emplace(std::move(*ctx));
        ASSERT_TRUE(gui_.init(width, height).ok());
        ASSERT_TRUE(renderer_.init().ok());
    }

    void startViewer(const devices::SyntheticConfig& config, Settings settings = {}) {
        ASSERT_NO_FATAL_FAILURE(
            start(std::make_unique<devices::SyntheticDevice>(config), "synthetic", std::move(settings)));
        // Let the first frame arrive so every panel has content.
        ASSERT_TRUE(viewer_->update(0.0, std::chrono::seconds(5)));
        frame(0.0);
    }

    // The instrument on `device`, and a viewer on it; nothing waited for.
    void start(std::unique_ptr<devices::Device> device, std::string spec, Settings settings = {}) {
        viewer_.reset();
        instrument_.reset();
        instrument_ = std::make_unique<engine::Instrument>(std::move(device), std::move(spec));
        viewer_ = std::make_unique<Viewer>(*instrument_, renderer_, std::move(settings));
        instrument_->start();
    }

    void TearDown() override {
        viewer_.reset();
        instrument_.reset();
    }

    // One UI frame at time t: the viewer renders, the panels are drawn with whatever input is set, and the
    // frame counts as shown.
    void frame(double t) {
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(t);
        viewer_->drawUi();
        gui_.render();
        viewer_->presented();
    }

    // Frames until `done` holds or `limit` passes (a bound in time, not in frames: frames with nothing new
    // are fast, and what they wait for may take a busy machine seconds); returns done().
    bool frameUntil(const std::function<bool()>& done,
                    std::chrono::seconds limit = std::chrono::seconds(20)) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        while (!done() && std::chrono::steady_clock::now() < deadline) {
            frame(0.0);
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        return done();
    }

    // Frames until a new device frame's result is shown (or 5 s pass).
    bool nextFrame(double t) {
        gui_.newFrame(1.0f / 60.0f);
        const bool fresh = viewer_->update(t, std::chrono::seconds(5));
        viewer_->drawUi();
        gui_.render();
        viewer_->presented();
        return fresh;
    }

    // Finds a widget by label inside a panel by hovering candidate positions until ImGui reports the
    // widget's ID as hovered: no coordinates are hard-coded, so a layout change cannot fool the test.
    std::optional<ImVec2> locate(const char* window, const char* label, float widthFraction = 0.6f,
                                 float xStep = 24.0f) {
        ImGuiWindow* w = ImGui::FindWindowByName(window);
        if (!w)
            return std::nullopt;
        const ImGuiID id = w->GetID(label);
        for (float y = w->Pos.y; y < w->Pos.y + w->Size.y; y += 3.0f) {
            for (float x = w->Pos.x + 12.0f; x < w->Pos.x + w->Size.x * widthFraction; x += xStep) {
                gui_.io().MousePos = ImVec2(x, y);
                gui_.newFrame(1.0f / 60.0f);
                viewer_->drawUi();
                ImGui::EndFrame();
                if (ImGui::GetCurrentContext()->HoveredId == id)
                    return ImVec2(x, y);
            }
        }
        return std::nullopt;
    }

    void click(ImVec2 at, double t) {
        gui_.io().MousePos = at;
        frame(t);
        gui_.io().MouseDown[0] = true;
        frame(t);
        gui_.io().MouseDown[0] = false;
        frame(t);
    }

    // Opens a group of the Controls panel that starts collapsed by clicking its header, as a user would,
    // scrolling the panel down to it first where it is below the panel's edge, and then up to its top.
    void openControlsGroup(const char* header) {
        ImGuiWindow* w = ImGui::FindWindowByName(kControlsTitle);
        ASSERT_NE(w, nullptr);
        auto at = locate(kControlsTitle, header);
        if (!at) {
            ImGui::SetScrollY(w, w->ScrollMax.y);
            frame(0.0);
            at = locate(kControlsTitle, header);
        }
        ASSERT_TRUE(at) << header;
        click(*at, 0.0);
        ASSERT_NE(w->StateStorage.GetInt(w->GetID(header), 0), 0) << header << " did not open";
        ImGui::SetScrollY(w, w->Scroll.y + at->y - w->Pos.y - w->TitleBarHeight() - 4.0f);
        frame(0.0);
    }

    void pressKey(int key, double t) {
        gui_.io().KeysDown[key] = true;
        frame(t);
        gui_.io().KeysDown[key] = false;
        frame(t);
    }

    std::vector<std::uint8_t> cloudSnapshot(double t) {
        viewer_->update(t);
        return renderer_.cloudTarget().readRgba();
    }

    const processing::ShownFrame& shown() const { return *viewer_->shown(); }

    static std::size_t litPixels(const std::vector<std::uint8_t>& rgba) {
        std::size_t n = 0;
        for (std::size_t i = 0; i < rgba.size(); i += 4)
            n += (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
        return n;
    }

    std::optional<render::EglContext> context_;
    HeadlessUi gui_;
    render::ViewRenderer renderer_;
    std::unique_ptr<engine::Instrument> instrument_;
    std::unique_ptr<Viewer> viewer_;
};

} // namespace dc::ui::test
