#include "ui/image_panel.h"

#include <algorithm>
#include <vector>

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

void drawSourceTabs(const SourceTabs& tabs) {
    if (tabs.names.size() < 2 || !tabs.selected)
        return;
    // Radio buttons, not an ImGui tab bar: a tab bar keeps its own choice per window, and every image
    // panel must show the one choice.
    int selected = static_cast<int>(*tabs.selected);
    for (std::size_t i = 0; i < tabs.names.size(); ++i) {
        if (i > 0)
            ImGui::SameLine();
        ImGui::RadioButton(tabs.names[i].c_str(), &selected, static_cast<int>(i));
    }
    *tabs.selected = static_cast<std::size_t>(selected);
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

constexpr ImU32 kDrawingColour = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kRegionColour = IM_COL32(255, 255, 0, 255);
// A lasso's vertices are at least this far apart on screen: a slow drag does not pile up hundreds of them.
constexpr float kLassoSpacingPixels = 3.0f;

// The lasso being drawn: one at a time, as ImGui holds one active item at a time; `owner` is the button
// drawing it, so a drag started on another panel starts a new one.
struct Lasso {
    ImGuiID owner = 0;
    bool active = false;
    std::vector<ImVec2> screen;
};
Lasso& lasso() {
    static Lasso l;
    return l;
}

// Shift held as the drag starts: vertices where the mouse goes, a polyline while it drags, closed on
// release into result.drawnPolygon (fewer than 3 vertices draw nothing). Whether the button's drag is a
// lasso, up to and including the frame it is released on.
bool dragLasso(const ImageRect& shown, ImGuiID id, PanelResult& result) {
    Lasso& l = lasso();
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemActivated())
        l = {id, io.KeyShift, {io.MouseClickedPos[0]}};
    // A lasso whose button let go unseen (its window closed mid-drag) is over, not waiting for a release.
    const bool held = ImGui::IsItemActive() || ImGui::IsItemDeactivated();
    if (l.owner != id || !l.active || !held)
        return false;
    const ImVec2 last = l.screen.back();
    const float dx = io.MousePos.x - last.x, dy = io.MousePos.y - last.y;
    if (dx * dx + dy * dy >= kLassoSpacingPixels * kLassoSpacingPixels &&
        l.screen.size() < kMaxPolygonVertices)
        l.screen.push_back(io.MousePos);
    if (ImGui::IsItemActive() && l.screen.size() >= 2)
        ImGui::GetWindowDrawList()->AddPolyline(l.screen.data(), static_cast<int>(l.screen.size()),
                                                kDrawingColour, ImDrawFlags_None, 2.0f);
    if (!ImGui::IsItemDeactivated())
        return true;
    l.active = false;
    if (l.screen.size() >= 3) {
        std::vector<ImVec2> fractions;
        for (const ImVec2& p : l.screen)
            fractions.push_back(imageFractionAt(shown, p));
        result.drawnPolygon = std::move(fractions);
    }
    return true;
}

// An invisible button over the image holds the mouse while it drags, so the drag draws rather than moves
// the window; the rectangle goes from where the button was pressed to where it is released.
void dragRectangle(const ImageRect& shown, PanelResult& result) {
    const ImVec2 size{shown.max.x - shown.min.x, shown.max.y - shown.min.y};
    if (size.x < 1.0f || size.y < 1.0f)
        return;
    const ImVec2 cursor = ImGui::GetCursorScreenPos();
    ImGui::SetCursorScreenPos(shown.min);
    const ImGuiID id = ImGui::GetID("##drawRect");
    ImGui::InvisibleButton("##drawRect", size);
    ImGui::SetCursorScreenPos(cursor);
    if (dragLasso(shown, id, result))
        return;
    const ImGuiIO& io = ImGui::GetIO();
    const ImVec2 a = imageFractionAt(shown, io.MouseClickedPos[0]);
    const ImVec2 b = imageFractionAt(shown, io.MousePos);
    const ImVec4 rect{std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
    // Non-zero once the mouse moved past ImGui's drag threshold, on the frame it is released too.
    const ImVec2 delta = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left);
    const bool dragged = delta.x != 0.0f || delta.y != 0.0f;
    if (ImGui::IsItemActive() && dragged)
        outlineImageRect(shown, rect, kDrawingColour);
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
        if (roi.polygon.empty())
            outlineImageRect(shown, *roi.outline, kRegionColour);
        else
            outlineImagePolygon(shown, roi.polygon, kRegionColour);
    }
    interactWithImage(shown, source, result, roi.drawable && shownAtAll);
}

void outlineImagePolygon(const ImageRect& shown, const std::vector<ImVec2>& fractions, ImU32 colour) {
    std::vector<ImVec2> screen;
    for (const ImVec2& f : fractions)
        screen.push_back(screenAtFraction(shown, f));
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(shown.min, shown.max, true);
    draw->AddPolyline(screen.data(), static_cast<int>(screen.size()), colour, ImDrawFlags_Closed, 2.0f);
    draw->PopClipRect();
}

void outlineImageRect(const ImageRect& shown, ImVec4 fractions, ImU32 colour) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(shown.min, shown.max, true);
    draw->AddRect(screenAtFraction(shown, {fractions.x, fractions.y}),
                  screenAtFraction(shown, {fractions.z, fractions.w}), colour, 0.0f, 0, 2.0f);
    draw->PopClipRect();
}

} // namespace dc::ui
