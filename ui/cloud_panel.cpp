#include "ui/panels.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>

namespace dc::ui {

namespace {
constexpr float kOrbitRadiansPerPixel = 0.008f;
constexpr float kPanMetersPerPixel = 0.002f;
constexpr float kZoomPerWheelStep = 1.1f;
// A press is a click until the mouse moves this far from where it went down.
constexpr float kClickSlopPixels = 3.0f;

// A drag of `button` on the view, moved past the click slop. Not in the frame of the press: the mouse may
// have jumped there within that frame, and the jump is no drag.
bool dragging(ImGuiMouseButton button) {
    return ImGui::IsItemActive() && ImGui::IsMouseDragging(button, kClickSlopPixels) &&
           !ImGui::IsMouseClicked(button);
}

// `gizmoOwns`: the left button is the gizmo's (pressed on a handle), so it neither orbits nor resets.
bool applyMouse(CloudSettings& cloud, bool gizmoOwns) {
    const ImGuiIO& io = ImGui::GetIO();
    bool changed = false;
    if (!gizmoOwns && dragging(ImGuiMouseButton_Left)) {
        cloud.orbit.yawRadians += io.MouseDelta.x * kOrbitRadiansPerPixel;
        cloud.orbit.pitchRadians += io.MouseDelta.y * kOrbitRadiansPerPixel;
        changed = true;
    }
    if (dragging(ImGuiMouseButton_Right) || dragging(ImGuiMouseButton_Middle)) {
        cloud.orbit.panMeters.x += io.MouseDelta.x * kPanMetersPerPixel;
        cloud.orbit.panMeters.y -= io.MouseDelta.y * kPanMetersPerPixel;
        changed = true;
    }
    if (ImGui::IsItemHovered() && io.MouseWheel != 0.0f) {
        cloud.orbit.zoom *= std::pow(kZoomPerWheelStep, io.MouseWheel);
        changed = true;
    }
    if (!gizmoOwns && ImGui::IsItemHovered() && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) {
        cloud.orbit = {};
        changed = true;
    }
    if (changed)
        sanitize(cloud);
    return changed;
}

// The gizmo's handle under the mouse; a left press on one takes the button until it is released, and each
// frame it is dragged (past the click slop) steps the source from where the last step left the mouse, so
// the handle keeps up with it. Returns whether the gizmo owns the left button this frame (the release's
// included: that is no click either). Called right after the view's button, whose item state it reads.
bool driveGizmo(CloudGizmo& gizmo, ImVec2 origin, ImVec2 size, CloudPanelResult& result) {
    const ImGuiIO& io = ImGui::GetIO();
    const GizmoView view{gizmo.worldToClip, {size.x, size.y}};
    const glm::dvec2 mouse{io.MousePos.x - origin.x, io.MousePos.y - origin.y};
    gizmo.hovered.reset();
    if (!gizmo.held && ImGui::IsItemHovered())
        gizmo.hovered = pickGizmo(projectGizmo(view, gizmo.originWorld), mouse);
    if (!gizmo.held && gizmo.hovered && ImGui::IsItemHovered() &&
        ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        gizmo.held = gizmo.hovered;
        gizmo.heldAt = mouse;
    }
    if (!gizmo.held)
        return false;
    if (!io.MouseDown[ImGuiMouseButton_Left]) {
        gizmo.held.reset();
        return true;
    }
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, kClickSlopPixels) && mouse != gizmo.heldAt) {
        result.gizmoStep = gizmoStep(*gizmo.held, view, gizmo.originWorld, gizmo.heldAt, mouse);
        gizmo.heldAt = mouse;
    }
    return true;
}

// World x red, y green, z blue; the handle held, or else the one under the mouse, yellow and thicker.
void drawGizmo(const CloudGizmo& gizmo, ImVec2 origin, ImVec2 size) {
    constexpr std::array<ImU32, 3> kAxisColours{IM_COL32(235, 64, 64, 255), IM_COL32(64, 210, 64, 255),
                                                IM_COL32(80, 130, 255, 255)};
    constexpr ImU32 kLit = IM_COL32(255, 220, 64, 255);
    constexpr float kArrowHeadPixels = 10.0f;
    const GizmoShape shape = projectGizmo({gizmo.worldToClip, {size.x, size.y}}, gizmo.originWorld);
    if (!shape.origin)
        return;
    const auto screen = [&](const glm::dvec2& p) {
        return ImVec2(origin.x + static_cast<float>(p.x), origin.y + static_cast<float>(p.y));
    };
    const std::optional<GizmoHandle> lit = gizmo.held ? gizmo.held : gizmo.hovered;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(origin, {origin.x + size.x, origin.y + size.y}, true);
    std::vector<ImVec2> points;
    for (std::size_t h = 0; h < kGizmoHandles; ++h) {
        const auto handle = static_cast<GizmoHandle>(h);
        const ImU32 colour = lit == handle ? kLit : kAxisColours[static_cast<std::size_t>(axisOf(handle))];
        const float thickness = lit == handle ? 4.0f : 2.0f;
        for (const std::vector<glm::dvec2>& line : shape.lines[h]) {
            points.clear();
            for (const glm::dvec2& p : line)
                points.push_back(screen(p));
            draw->AddPolyline(points.data(), static_cast<int>(points.size()), colour, 0, thickness);
        }
        if (turns(handle) || shape.lines[h].empty())
            continue;
        const std::vector<glm::dvec2>& shaft = shape.lines[h].back();
        const glm::dvec2 along = shaft.back() - shaft.front();
        if (glm::length(along) < 1.0)
            continue;
        const glm::dvec2 d = glm::normalize(along) * static_cast<double>(kArrowHeadPixels);
        const glm::dvec2 side{-d.y * 0.5, d.x * 0.5};
        draw->AddTriangleFilled(screen(shaft.back() + d), screen(shaft.back() + side),
                                screen(shaft.back() - side), colour);
    }
    draw->AddCircleFilled(screen(*shape.origin), 4.0f, IM_COL32(255, 255, 255, 255));
    draw->PopClipRect();
}

// The centroid of a simple polygon (the mean of its corners when it has no area, e.g. collinear anchors).
ImVec2 centroid(const std::vector<ImVec2>& p) {
    double area2 = 0.0, cx = 0.0, cy = 0.0, mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const ImVec2 a = p[i], b = p[(i + 1) % p.size()];
        const double cross = static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y;
        area2 += cross;
        cx += (a.x + b.x) * cross;
        cy += (a.y + b.y) * cross;
        mx += a.x;
        my += a.y;
    }
    const double n = static_cast<double>(p.size());
    if (std::abs(area2) < 1.0)
        return {static_cast<float>(mx / n), static_cast<float>(my / n)};
    return {static_cast<float>(cx / (3.0 * area2)), static_cast<float>(cy / (3.0 * area2))};
}

// The Quality panel's region in the yellow that outlines it on the image panels, under the anchors.
void drawRoiOutline(const CloudOverlay& overlay, ImVec2 origin, ImVec2 size) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(origin, {origin.x + size.x, origin.y + size.y}, true);
    std::vector<ImVec2> points;
    for (const std::vector<ImVec2>& line : overlay.roiOutline) {
        points.clear();
        for (const ImVec2 f : line)
            points.emplace_back(origin.x + f.x * size.x, origin.y + f.y * size.y);
        draw->AddPolyline(points.data(), static_cast<int>(points.size()), IM_COL32(255, 255, 0, 255), 0,
                          2.0f);
    }
    draw->PopClipRect();
}

// Anchors as numbered dots, the edges between them (closed into a polygon from three on), each edge's
// length at its midpoint and the area at the centroid, on dark backdrops, moved apart where they collide.
std::vector<LabelBox> drawOverlay(const CloudOverlay& overlay, ImVec2 origin, ImVec2 size) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    std::vector<ImVec2> points;
    for (const ImVec2 f : overlay.anchors)
        points.emplace_back(origin.x + f.x * size.x, origin.y + f.y * size.y);
    const ImU32 line = IM_COL32(255, 214, 64, 255);
    const ImVec2 middle = points.size() >= 3 ? centroid(points) : ImVec2(origin.x + size.x * 0.5f, origin.y);
    std::vector<std::string> texts;
    std::vector<ImVec2> at, away, sizes;
    const float fontSize = ImGui::GetFontSize() * 1.25f;
    ImFont* font = ImGui::GetFont();
    const auto textSize = [&](const std::string& t) {
        return font->CalcTextSizeA(fontSize, FLT_MAX, 0.0f, t.c_str());
    };
    for (const auto& [first, label] : overlay.segments) {
        const auto i = static_cast<std::size_t>(first);
        if (i >= points.size() || points.size() < 2)
            continue;
        const ImVec2 a = points[i], b = points[(i + 1) % points.size()];
        draw->AddLine(a, b, line, 2.0f);
        const ImVec2 mid{(a.x + b.x) * 0.5f, (a.y + b.y) * 0.5f};
        // Away from the polygon's middle, so a label moved off its edge moves outwards.
        const float dx = mid.x - middle.x, dy = mid.y - middle.y, len = std::hypot(dx, dy);
        texts.push_back(label);
        at.push_back(mid);
        away.push_back(len > 1e-3f ? ImVec2(dx / len, dy / len) : ImVec2(0.0f, -1.0f));
        sizes.push_back(textSize(label));
    }
    if (!overlay.summary.empty() && points.size() >= 3) {
        texts.push_back(overlay.summary);
        at.push_back(middle);
        away.emplace_back(0.0f, 1.0f);
        sizes.push_back(textSize(overlay.summary));
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
        draw->AddCircle(points[i], 6.0f, line, 12, 2.0f);
        draw->AddText({points[i].x + 8.0f, points[i].y + 2.0f}, IM_COL32(255, 255, 255, 255),
                      std::to_string(i + 1).c_str());
    }
    std::vector<LabelBox> boxes = placeLabels(at, sizes, away);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const LabelBox& b = boxes[i];
        draw->AddRectFilled({b.min.x - 4.0f, b.min.y - 2.0f}, {b.max.x + 4.0f, b.max.y + 2.0f},
                            IM_COL32(0, 0, 0, 170), 4.0f);
        draw->AddText(font, fontSize, b.min, IM_COL32(255, 255, 255, 255), texts[i].c_str());
    }
    return boxes;
}

// The mouse over the view in cloud-image pixels, and whether the left button was clicked (released
// without dragging) there.
void readPointer(CloudPanelResult& result, ImVec2 origin, ImVec2 size) {
    const ImGuiIO& io = ImGui::GetIO();
    if (!ImGui::IsItemHovered())
        return;
    const ImVec2 at{io.MousePos.x - origin.x, io.MousePos.y - origin.y};
    result.hoverPixels = at;
    // The release that ends a double-click (a view reset) is not a click of its own.
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseClickedLastCount[ImGuiMouseButton_Left] < 2 &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] <= kClickSlopPixels * kClickSlopPixels &&
        at.x >= 0.0f && at.y >= 0.0f && at.x < size.x && at.y < size.y)
        result.clickPixels = at;
    result.doubleClicked = ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left);
}

// What the draw callback copies where: ImGui keeps only a pointer until the frame is rendered, and there
// is one cloud panel.
struct CloudCopy {
    const render::RenderTarget* picture = nullptr;
    ImVec2 min, max; // on screen
};
CloudCopy gCloudCopy;

// Screen coordinates of the frame being rendered to GL's framebuffer pixels, bottom-left origin.
render::PixelRect framebufferRect(const ImDrawData& data, ImVec2 min, ImVec2 max) {
    const ImVec2 s = data.FramebufferScale;
    const float height = data.DisplaySize.y * s.y;
    const float x0 = (min.x - data.DisplayPos.x) * s.x, x1 = (max.x - data.DisplayPos.x) * s.x;
    const float y0 = (min.y - data.DisplayPos.y) * s.y, y1 = (max.y - data.DisplayPos.y) * s.y;
    return {static_cast<int>(std::lround(x0)), static_cast<int>(std::lround(height - y1)),
            static_cast<int>(std::lround(x1 - x0)), static_cast<int>(std::lround(y1 - y0))};
}

void copyCloud(const ImDrawList*, const ImDrawCmd* command) {
    const auto& copy = *static_cast<const CloudCopy*>(command->UserCallbackData);
    const ImDrawData& data = *ImGui::GetDrawData();
    const ImVec4 clip = command->ClipRect;
    copy.picture->blitInto(framebufferRect(data, copy.min, copy.max),
                           framebufferRect(data, {clip.x, clip.y}, {clip.z, clip.w}));
}

// The cloud's pixels, copied into the window where ImGui would have drawn them (windows above it still
// draw over it, in order).
void drawPicture(const render::RenderTarget& picture, ImVec2 min, ImVec2 max) {
    if (picture.empty())
        return;
    gCloudCopy = {&picture, min, max};
    ImDrawList* list = ImGui::GetWindowDrawList();
    list->AddCallback(copyCloud, &gCloudCopy);
    list->AddCallback(ImDrawCallback_ResetRenderState, nullptr);
}

} // namespace

std::vector<LabelBox> placeLabels(const std::vector<ImVec2>& anchors, const std::vector<ImVec2>& sizes,
                                  const std::vector<ImVec2>& away) {
    // Boxes keep a small gap (the backdrop's margin) between them.
    constexpr float kGap = 6.0f;
    const auto overlaps = [](const LabelBox& a, const LabelBox& b) {
        return a.min.x < b.max.x + kGap && b.min.x < a.max.x + kGap && a.min.y < b.max.y + kGap &&
               b.min.y < a.max.y + kGap;
    };
    std::vector<LabelBox> placed;
    for (std::size_t i = 0; i < anchors.size(); ++i) {
        const ImVec2 half{sizes[i].x * 0.5f, sizes[i].y * 0.5f};
        LabelBox box;
        for (int step = 0; step < 200; ++step) {
            const ImVec2 c{anchors[i].x + away[i].x * 4.0f * static_cast<float>(step),
                           anchors[i].y + away[i].y * 4.0f * static_cast<float>(step)};
            box = {{c.x - half.x, c.y - half.y}, {c.x + half.x, c.y + half.y}, anchors[i]};
            if (std::none_of(placed.begin(), placed.end(),
                             [&](const LabelBox& p) { return overlaps(box, p); }))
                break;
        }
        placed.push_back(box);
    }
    return placed;
}

CloudPanelResult drawCloudPanel(const render::RenderTarget& picture, CloudSettings& cloud,
                                const CloudOverlay& overlay, const std::string& message, bool zoomed,
                                bool* open, CloudGizmo* gizmo) {
    CloudPanelResult result;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0.0f, 0.0f));
    // The picture is copied over the whole content region, replacing what is there: a background under it
    // would be filled and then overwritten, and on a software rasteriser that fill is a panel-sized pass of
    // every frame.
    result.panel.visible = ImGui::Begin(
        kCloudTitle, open, picture.empty() ? ImGuiWindowFlags_None : ImGuiWindowFlags_NoBackground);
    ImGui::PopStyleVar();
    result.panel.windowPos = ImGui::GetWindowPos();
    result.panel.windowSize = ImGui::GetWindowSize();
    if (!result.panel.visible) {
        ImGui::End();
        return result;
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    result.wantedWidth = static_cast<int>(avail.x);
    result.wantedHeight = static_cast<int>(avail.y);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    if (avail.x >= 1.0f && avail.y >= 1.0f) {
        // One button over the whole view takes the mouse, so dragging the cloud never moves the window.
        ImGui::InvisibleButton("##cloud", avail,
                               ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                                   ImGuiButtonFlags_MouseButtonMiddle);
        ImGui::SetItemAllowOverlap(); // the zoom button drawn over the view must still take clicks
        const bool gizmoOwns = gizmo && driveGizmo(*gizmo, origin, avail, result);
        result.viewChanged = applyMouse(cloud, gizmoOwns);
        readPointer(result, origin, avail);
        if (gizmoOwns) {
            result.clickPixels.reset();
            result.doubleClicked = false;
        }
        drawPicture(picture, origin, {origin.x + avail.x, origin.y + avail.y});
        drawRoiOutline(overlay, origin, avail);
        result.labels = drawOverlay(overlay, origin, avail);
        if (gizmo)
            drawGizmo(*gizmo, origin, avail);
        ImGui::SetCursorScreenPos(
            {origin.x + avail.x - ImGui::CalcTextSize("Restore").x - 24.0f, origin.y + 8.0f});
        result.panel.toggleZoom = ImGui::SmallButton(zoomed ? "Restore" : "Zoom");
    }
    if (!message.empty()) {
        ImGui::SetCursorScreenPos({origin.x + 12.0f, origin.y + 12.0f});
        ImGui::PushTextWrapPos(origin.x + avail.x - 12.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.4f, 1.0f), "%s", message.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
    return result;
}

} // namespace dc::ui
