// The window draws a frame only where it changed (FrameDamage). Checked against the same frame drawn whole,
// pixel for pixel, over a stream of frames: the view turning, the mouse moving over the panels (readouts
// coming and going), a panel closed and opened, a setting changed.

#include "ui/frame_damage.h"
#include "ui_fixture.h"

#include <backends/imgui_impl_opengl3.h>

namespace dc::ui::test {
namespace {

// A window's draw list by hand: one textured quad over (x0, y0)-(x1, y1), clipped to `clip`.
struct HandList {
    explicit HandList(const char* owner) : list(nullptr) { list._OwnerName = owner; }
    void quad(float x0, float y0, float x1, float y1, ImTextureID texture, ImVec4 clip) {
        const auto first = static_cast<ImDrawIdx>(list.VtxBuffer.Size);
        for (const ImVec2 p : {ImVec2(x0, y0), ImVec2(x1, y0), ImVec2(x1, y1), ImVec2(x0, y1)})
            list.VtxBuffer.push_back({p, {0.0f, 0.0f}, 0xffffffff});
        for (const int i : {0, 1, 2, 0, 2, 3})
            list.IdxBuffer.push_back(static_cast<ImDrawIdx>(first + i));
        ImDrawCmd c;
        c.ClipRect = clip;
        c.TextureId = texture;
        c.IdxOffset = static_cast<unsigned>(list.IdxBuffer.Size - 6);
        c.ElemCount = 6;
        list.CmdBuffer.push_back(c);
    }
    ImDrawList list;
};

ImDrawData handData(std::vector<ImDrawList*>& lists) {
    ImDrawData data;
    data.Valid = true;
    data.CmdLists = lists.data();
    data.CmdListsCount = static_cast<int>(lists.size());
    data.DisplayPos = {0.0f, 0.0f};
    data.DisplaySize = {1280.0f, 720.0f};
    data.FramebufferScale = {1.0f, 1.0f};
    return data;
}

using Rects = std::vector<DamageRect>;
const Rects kWhole{{0, 0, 1280, 720}};
const auto kFont = reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(1));
const auto kImage = reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(2));
const ImVec4 kEverywhere{0.0f, 0.0f, 1280.0f, 720.0f};

TEST(FrameDamage, AClipRectangleSnapsToThePixelsTheBackendScissors) {
    HandList window("window");
    window.quad(0, 0, 10, 10, kFont, {10.5f, 20.25f, 300.7f, 400.9f});
    std::vector<ImDrawList*> lists{&window.list};
    ImDrawData data = handData(lists);
    snapClipRects(data);
    // The backend: x 10, width (int)290.2; GL y (int)(720 - 400.9) = 319, height (int)380.65.
    const ImVec4 c = window.list.CmdBuffer[0].ClipRect;
    EXPECT_EQ(c.x, 10.0f);
    EXPECT_EQ(c.z, 300.0f);
    EXPECT_EQ(c.y, 720.0f - (319.0f + 380.0f));
    EXPECT_EQ(c.w, 720.0f - 319.0f);
}

TEST(FrameDamage, OnlyTheWindowsThatChangedAndTheImagesWhoseTexturesChangedAreDamaged) {
    HandList controls("controls"), cloud("cloud");
    controls.quad(0, 0, 300, 700, kFont, kEverywhere);
    cloud.quad(300, 0, 1280, 700, kFont, kEverywhere);
    cloud.quad(400, 100, 600, 200, kImage, kEverywhere);
    std::vector<ImDrawList*> lists{&controls.list, &cloud.list};
    ImDrawData data = handData(lists);
    FrameDamage damage;
    EXPECT_EQ(damage.update(data, 7, kFont), kWhole) << "first: whole";
    EXPECT_TRUE(damage.update(data, 7, kFont).empty()) << "the same frame again";
    // The image's rectangle, with the pixel of margin rounding may need.
    EXPECT_EQ(damage.update(data, 8, kFont), Rects({{399, 99, 601, 201}})) << "new content";
    controls.list.VtxBuffer[0].pos.x = 1.0f;
    EXPECT_EQ(damage.update(data, 8, kFont), Rects({{0, 0, 301, 701}})) << "one window moved";
    HandList tooltip("tooltip");
    tooltip.quad(500, 500, 600, 550, kFont, kEverywhere);
    lists.push_back(&tooltip.list);
    EXPECT_EQ(damage.update(data = handData(lists), 8, kFont), Rects({{499, 499, 601, 551}}))
        << "one appeared";
    lists.pop_back();
    EXPECT_EQ(damage.update(data = handData(lists), 8, kFont), Rects({{499, 499, 601, 551}})) << "and went";
    std::swap(lists[0], lists[1]);
    EXPECT_EQ(damage.update(data, 8, kFont), kWhole) << "another order";
    damage.forget();
    std::swap(lists[0], lists[1]);
    EXPECT_EQ(damage.update(data, 8, kFont), kWhole) << "forgotten";
}

class FrameDamageTest : public UiTest {
protected:
    void SetUp() override {
        UiTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_TRUE(kept_.resize(kWidth, kHeight).ok());
        ASSERT_TRUE(whole_.resize(kWidth, kHeight).ok());
    }

    // One UI frame drawn both ways: where it changed, into kept_, which holds the frames before it; and
    // whole, into whole_. Returns the pixels drawn into kept_.
    long long frameBothWays(double t) {
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(t);
        viewer_->drawUi();
        ImGui::Render();
        ImDrawData& data = *ImGui::GetDrawData();
        snapClipRects(data);
        const std::vector<DamageRect> rects =
            damage_.update(data, renderer_.contentVersion(), ImGui::GetIO().Fonts->TexID);
        long long area = 0;
        drawDamaged(data, rects, [&](const DamageRect& r) {
            kept_.bindAndClearWithin(pixelRectOf(r, kHeight), 0.1f, 0.1f, 0.12f);
            area += static_cast<long long>(r.x1 - r.x0) * (r.y1 - r.y0);
        });
        whole_.bindAndClear(0.1f, 0.1f, 0.12f);
        ImGui_ImplOpenGL3_RenderDrawData(&data);
        viewer_->presented(!rects.empty());
        return area;
    }

    // A frame both ways, and whether their pictures are the same; counts the frames drawn in part.
    ::testing::AssertionResult sameBothWays(double t) {
        const long long area = frameBothWays(t);
        partFrames_ += area > 0 && area < static_cast<long long>(kWidth) * kHeight;
        if (kept_.readRgba() == whole_.readRgba())
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "the frame drawn in parts (" << area << " pixels) differs";
    }

    static ImVec2 centreOf(const char* title) {
        const ImGuiWindow* w = ImGui::FindWindowByName(title);
        return w ? ImVec2(w->Pos.x + w->Size.x * 0.5f, w->Pos.y + w->Size.y * 0.5f) : ImVec2(-1.0f, -1.0f);
    }

    static constexpr int kWidth = 1280, kHeight = 720; // the headless UI's size
    render::RenderTarget kept_{render::Sampling::Linear, render::DepthBuffer::Without};
    render::RenderTarget whole_{render::Sampling::Linear, render::DepthBuffer::Without};
    FrameDamage damage_;
    int partFrames_ = 0;
};

TEST_F(FrameDamageTest, AFrameDrawnWhereItChangedIsTheFrameDrawnWhole) {
    for (int i = 0; i < 30; ++i)
        ASSERT_TRUE(sameBothWays(i / 30.0)) << "streaming, the view turning: frame " << i;
    for (const char* panel : {kDepthTitle, kConfidenceTitle, kCameraTitle, kCloudTitle, kControlsTitle}) {
        gui_.io().MousePos = centreOf(panel);
        for (int i = 0; i < 3; ++i)
            ASSERT_TRUE(sameBothWays(1.0 + i / 30.0)) << "the mouse over " << panel << ": frame " << i;
    }
    viewer_->settings().panels.confidence = false;
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(sameBothWays(2.0)) << "the confidence panel closed: frame " << i;
    viewer_->settings().panels.confidence = true;
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(sameBothWays(2.0)) << "the confidence panel opened: frame " << i;
    viewer_->settings().depthRange.colormap = render::Colormap::Viridis;
    viewer_->settings().cloud.motion.enabled = false;
    for (int i = 0; i < 10; ++i)
        ASSERT_TRUE(sameBothWays(3.0)) << "another colormap, the view still: frame " << i;
    EXPECT_GT(partFrames_, 30) << "most frames are drawn in parts: the comparison is of something";
}

// The benches composite as the window does on hardware GL, where a swap shows the whole back buffer: a
// frame that changed anywhere is drawn whole. Drawn in parts, a pixel outside what changed keeps whatever
// was there; drawn whole, it is drawn again.
TEST_F(FrameDamageTest, AChangedFrameDrawnWholeRedrawsEvenWhereItDidNotChange) {
    const render::PixelRect corner{0, kHeight - 4, 4, 4}; // the controls' title bar, which does not change
    const auto scribbledOver = [&](bool whole) {
        gui_.setDrawsChangedFramesWhole(whole);
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(0.0);
        viewer_->drawUi();
        viewer_->presented(gui_.renderIfChanged(renderer_.contentVersion()));
        gui_.target().bindAndClearWithin(corner, 1.0f, 0.0f, 1.0f);
        gui_.newFrame(1.0f / 60.0f);
        viewer_->update(0.5); // the view turns: the cloud changes, the controls do not
        viewer_->drawUi();
        EXPECT_TRUE(gui_.renderIfChanged(renderer_.contentVersion()));
        viewer_->presented(true);
        const std::vector<std::uint8_t> rgba = gui_.target().readRgba();
        return rgba[0] == 255 && rgba[1] == 0 && rgba[2] == 255; // the top row comes first
    };
    EXPECT_TRUE(scribbledOver(false)) << "in parts, the unchanged corner is not drawn again";
    EXPECT_FALSE(scribbledOver(true)) << "whole, it is";
}

} // namespace
} // namespace dc::ui::test
