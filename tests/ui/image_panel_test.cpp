// An image panel's image is opaque, so its window fills the background around the image and never under
// it (on software GL a fill under the image is a panel-sized pass of every frame for nothing), and the two
// together still cover the window below its title bar.

#include "panel_fixture.h"
#include "render/rgba_texture.h"
#include "ui/panels.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace dc::ui::test {
namespace {

bool insideTriangle(ImVec2 p, ImVec2 a, ImVec2 b, ImVec2 c) {
    const auto side = [](ImVec2 p0, ImVec2 p1, ImVec2 q) {
        return (p1.x - p0.x) * (q.y - p0.y) - (p1.y - p0.y) * (q.x - p0.x);
    };
    const float d0 = side(a, b, p), d1 = side(b, c, p), d2 = side(c, a, p);
    return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

// Whether a triangle of `list` in colour `colour` covers `p`.
bool filledAt(const ImDrawList& list, ImU32 colour, ImVec2 p) {
    for (int i = 0; i + 2 < list.IdxBuffer.Size; i += 3) {
        const ImDrawVert& a = list.VtxBuffer[list.IdxBuffer[i]];
        const ImDrawVert& b = list.VtxBuffer[list.IdxBuffer[i + 1]];
        const ImDrawVert& c = list.VtxBuffer[list.IdxBuffer[i + 2]];
        if (a.col == colour && b.col == colour && c.col == colour && insideTriangle(p, a.pos, b.pos, c.pos))
            return true;
    }
    return false;
}

const ImDrawList* listOf(const ImDrawData& data, const char* owner) {
    for (int i = 0; i < data.CmdListsCount; ++i)
        if (std::strcmp(data.CmdLists[i]->_OwnerName, owner) == 0)
            return data.CmdLists[i];
    return nullptr;
}

TEST_F(PanelTest, AnImagePanelFillsItsBackgroundAroundTheImageAndNotUnderIt) {
    render::RgbaTexture texture;
    const std::vector<std::uint8_t> pixels(4 * 3 * 4, 200);
    texture.upload(4, 3, pixels.data());
    const PanelImage image{texture.id(), 4, 3, false};
    const ImVec2 pos{100.0f, 100.0f}, size{400.0f, 200.0f}; // wider than the image's 4:3: letterboxed
    draw_ = [&] {
        ImGui::SetNextWindowPos(pos);
        ImGui::SetNextWindowSize(size);
        drawCameraPanel(image, {}, CameraView{}, ProbeSource{}, RoiOverlay{}, nullptr);
    };
    frame();
    frame();
    const ImDrawData& data = *ImGui::GetDrawData();
    const ImDrawList* list = listOf(data, kCameraTitle);
    ASSERT_NE(list, nullptr);
    const ImU32 background = ImGui::GetColorU32(ImGuiCol_WindowBg);
    // The image's quad: the command that samples the texture.
    ImVec2 min{1e9f, 1e9f}, max{-1e9f, -1e9f};
    for (const ImDrawCmd& cmd : list->CmdBuffer)
        if (cmd.TextureId == reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture.id())))
            for (unsigned i = cmd.IdxOffset; i < cmd.IdxOffset + cmd.ElemCount; ++i) {
                const ImVec2 p = list->VtxBuffer[list->IdxBuffer[static_cast<int>(i)]].pos;
                min = {std::min(min.x, p.x), std::min(min.y, p.y)};
                max = {std::max(max.x, p.x), std::max(max.y, p.y)};
            }
    ASSERT_LT(min.x, max.x) << "the image was not drawn";
    ASSERT_GT(min.x, pos.x + 20.0f) << "the test needs a margin beside the image";
    int underImage = 0, around = 0, aroundMissing = 0;
    const float top = pos.y + ImGui::GetFrameHeight();
    for (float y = top + 0.5f; y < pos.y + size.y; y += 4.0f)
        for (float x = pos.x + 0.5f; x < pos.x + size.x; x += 4.0f) {
            const bool inImage = x > min.x && x < max.x && y > min.y && y < max.y;
            const bool filled = filledAt(*list, background, {x, y});
            underImage += inImage && filled;
            around += !inImage;
            aroundMissing += !inImage && !filled;
        }
    EXPECT_EQ(underImage, 0);
    EXPECT_GT(around, 100);
    EXPECT_EQ(aroundMissing, 0);
}

} // namespace
} // namespace dc::ui::test
