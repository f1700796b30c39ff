#include "ui/image_panel.h"

#include <algorithm>

namespace dc::ui {

namespace {

constexpr int kBackgroundChannel = 0;
constexpr int kContentChannel = 1;
// The causes of missing samples over the region: strong enough to read, weak enough to see the image under.
constexpr float kCauseOpacity = 0.7f;

// Fills [min, max) with `colour` except where `hole` (clamped to it) lies: up to four strips that share
// the hole's edges exactly, so the two cover every pixel once between them.
void fillAround(ImDrawList* list, ImVec2 min, ImVec2 max, const ImageRect& hole, ImU32 colour) {
    const ImVec2 h0{std::clamp(hole.min.x, min.x, max.x), std::clamp(hole.min.y, min.y, max.y)};
    const ImVec2 h1{std::clamp(hole.max.x, min.x, max.x), std::clamp(hole.max.y, min.y, max.y)};
    if (h1.x <= h0.x || h1.y <= h0.y) {
        list->AddRectFilled(min, max, colour);
        return;
    }
    list->AddRectFilled(min, {max.x, h0.y}, colour);
    list->AddRectFilled({min.x, h1.y}, max, colour);
    list->AddRectFilled({min.x, h0.y}, {h0.x, h1.y}, colour);
    list->AddRectFilled({h1.x, h0.y}, {max.x, h1.y}, colour);
}

} // namespace

bool beginImagePanel(const char* title, bool* open, PanelResult& result) {
    result.visible = ImGui::Begin(title, open, ImGuiWindowFlags_NoBackground);
    result.windowPos = ImGui::GetWindowPos();
    result.windowSize = ImGui::GetWindowSize();
    // The background goes into a channel drawn before the content, once the image's place is known.
    ImDrawList* list = ImGui::GetWindowDrawList();
    list->ChannelsSplit(2);
    list->ChannelsSetCurrent(kContentChannel);
    return result.visible;
}

void endImagePanel(const ImageRect& opaque) {
    ImDrawList* list = ImGui::GetWindowDrawList();
    list->ChannelsSetCurrent(kBackgroundChannel);
    // Where ImGui would fill the window's background (below the title bar), as it would fill it.
    const ImVec2 pos = ImGui::GetWindowPos();
    const ImVec2 size = ImGui::GetWindowSize();
    fillAround(list, {pos.x, pos.y + ImGui::GetFrameHeight()}, {pos.x + size.x, pos.y + size.y}, opaque,
               ImGui::GetColorU32(ImGuiCol_WindowBg));
    list->ChannelsMerge();
    ImGui::End();
}

namespace {

// An invisible button over the image holds the mouse while it drags, so the drag draws rather than moves
// the window; the rectangle goes from where the button was pressed to where it is released.
void dragRectangle(const ImageRect& shown, PanelResult& result) {
    const ImVec2 size{shown.max.x - shown.min.x, shown.max.y - shown.min.y};
    if (size.x < 1.0f || size.y < 1.0f)
        return;
    const ImVec2 cursor = ImGui::GetCursorScreenPos();
    ImGui::SetCursorScreenPos(shown.min);
    ImGui::InvisibleButton("##drawRect", size);
    ImGui::SetCursorScreenPos(cursor);
    const ImGuiIO& io = ImGui::GetIO();
    const ImVec2 a = imageFractionAt(shown, io.MouseClickedPos[0]);
    const ImVec2 b = imageFractionAt(shown, io.MousePos);
    const ImVec4 rect{std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
    // Non-zero once the mouse moved past ImGui's drag threshold, on the frame it is released too.
    const ImVec2 delta = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left);
    const bool dragged = delta.x != 0.0f || delta.y != 0.0f;
    if (ImGui::IsItemActive() && dragged)
        outlineImageRect(shown, rect, IM_COL32(255, 255, 255, 255));
    if (!ImGui::IsItemDeactivated())
        return;
    if (dragged)
        result.drawnRect = rect;
    else
        result.toggleZoom = true;
}

} // namespace

void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result,
                       bool dragDraws) {
    const float visible = shown.visibleMax.x - shown.visibleMin.x;
    result.shownWidth = visible > 0.0f ? static_cast<int>((shown.max.x - shown.min.x) / visible) : 0;
    if (dragDraws)
        dragRectangle(shown, result);
    const std::optional<ImVec2> at = imageFractionUnderMouse(shown);
    if (!at)
        return;
    result.probe = probeAtFraction(source, *at);
    if (!dragDraws && ImGui::IsMouseClicked(ImGuiMouseButton_Left))
        result.toggleZoom = true;
}

void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result,
                       const RoiOverlay& roi) {
    const bool shownAtAll = shown.max.x > shown.min.x;
    if (roi.outline && shownAtAll) {
        drawOverlayAt(roi.causes, shown, *roi.outline, kCauseOpacity);
        outlineImageRect(shown, *roi.outline, IM_COL32(255, 255, 0, 255));
    }
    interactWithImage(shown, source, result, roi.drawable && shownAtAll);
}

void outlineImageRect(const ImageRect& shown, ImVec4 fractions, ImU32 colour) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(shown.min, shown.max, true);
    draw->AddRect(screenAtFraction(shown, {fractions.x, fractions.y}),
                  screenAtFraction(shown, {fractions.z, fractions.w}), colour, 0.0f, 0, 2.0f);
    draw->PopClipRect();
}

} // namespace dc::ui
