#include "ui/frame_damage.h"

#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string_view>

namespace dc::ui {

namespace {

void append(std::vector<std::byte>& out, const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::byte*>(data);
    out.insert(out.end(), bytes, bytes + size);
}

template <class T> void appendValue(std::vector<std::byte>& out, const T& value) {
    append(out, &value, sizeof value);
}

// Every field the backend reads, one by one: ImDrawCmd's padding is not part of the picture.
void appendCommand(std::vector<std::byte>& out, const ImDrawCmd& c) {
    appendValue(out, c.ClipRect);
    appendValue(out, c.TextureId);
    appendValue(out, c.VtxOffset);
    appendValue(out, c.IdxOffset);
    appendValue(out, c.ElemCount);
    appendValue(out, c.UserCallback);
    appendValue(out, c.UserCallbackData);
}

int framebufferHeight(const ImDrawData& data) {
    return static_cast<int>(data.DisplaySize.y * data.FramebufferScale.y);
}

bool wholeScale(const ImDrawData& data) {
    const ImVec2 s = data.FramebufferScale;
    return s.x >= 1.0f && s.y >= 1.0f && std::floor(s.x) == s.x && std::floor(s.y) == s.y;
}

// The pixels the backend scissors a clip rectangle to, as it computes them.
DamageRect scissorOf(const ImDrawData& data, const ImVec4& clip) {
    const ImVec2 off = data.DisplayPos, s = data.FramebufferScale;
    const ImVec2 min((clip.x - off.x) * s.x, (clip.y - off.y) * s.y);
    const ImVec2 max((clip.z - off.x) * s.x, (clip.w - off.y) * s.y);
    if (max.x <= min.x || max.y <= min.y)
        return {};
    const int height = framebufferHeight(data);
    const int x = static_cast<int>(min.x), width = static_cast<int>(max.x - min.x);
    const int y = static_cast<int>(static_cast<float>(height) - max.y), h = static_cast<int>(max.y - min.y);
    return {x, height - (y + h), x + width, height - y};
}

ImVec4 clipOf(const ImDrawData& data, const DamageRect& r) {
    const ImVec2 off = data.DisplayPos, s = data.FramebufferScale;
    return {static_cast<float>(r.x0) / s.x + off.x, static_cast<float>(r.y0) / s.y + off.y,
            static_cast<float>(r.x1) / s.x + off.x, static_cast<float>(r.y1) / s.y + off.y};
}

DamageRect intersect(const DamageRect& a, const DamageRect& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

DamageRect unite(const DamageRect& a, const DamageRect& b) {
    if (a.empty())
        return b;
    if (b.empty())
        return a;
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

// The pixels a command's triangles cover, within its clip: an image's own rectangle, not its window's.
DamageRect drawnBy(const ImDrawData& data, const ImDrawList& list, const ImDrawCmd& c) {
    const DamageRect clip = scissorOf(data, c.ClipRect);
    if (c.UserCallback || c.ElemCount == 0)
        return clip;
    ImVec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    for (unsigned i = 0; i < c.ElemCount; ++i) {
        const ImVec2 p =
            list.VtxBuffer[static_cast<int>(c.VtxOffset + list.IdxBuffer[static_cast<int>(c.IdxOffset + i)])]
                .pos;
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    const ImVec2 off = data.DisplayPos, s = data.FramebufferScale;
    // A pixel outside the vertices' box by rounding still counts: one pixel of margin.
    const DamageRect box{static_cast<int>(std::floor((lo.x - off.x) * s.x)) - 1,
                         static_cast<int>(std::floor((lo.y - off.y) * s.y)) - 1,
                         static_cast<int>(std::ceil((hi.x - off.x) * s.x)) + 1,
                         static_cast<int>(std::ceil((hi.y - off.y) * s.y)) + 1};
    return intersect(clip, box);
}

// std::byte vectors compare element by element; a window's lists are hundreds of kilobytes, compared for
// every frame on the GL thread, so they are compared as one block.
bool sameBytes(const std::vector<std::byte>& a, const std::vector<std::byte>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size()) == 0);
}

long long area(const DamageRect& r) {
    return r.empty() ? 0 : static_cast<long long>(r.x1 - r.x0) * (r.y1 - r.y0);
}

// Unites two rectangles where their bounding box adds few pixels to what they cover: each pass over the
// draw lists costs, and so does each pixel drawn twice or drawn for nothing.
std::vector<DamageRect> merged(std::vector<DamageRect> rects) {
    std::erase_if(rects, [](const DamageRect& r) { return r.empty(); });
    for (bool again = true; again;) {
        again = false;
        for (std::size_t i = 0; i < rects.size() && !again; ++i)
            for (std::size_t j = i + 1; j < rects.size() && !again; ++j) {
                const DamageRect both = unite(rects[i], rects[j]);
                const long long covered =
                    area(rects[i]) + area(rects[j]) - area(intersect(rects[i], rects[j]));
                if (area(both) * 10 <= covered * 11) {
                    rects[i] = both;
                    rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(j));
                    again = true;
                }
            }
    }
    return rects;
}

} // namespace

std::vector<FrameDamage::List> FrameDamage::describe(const ImDrawData& data, ImTextureID fontTexture) {
    std::vector<List> lists(static_cast<std::size_t>(std::max(data.CmdListsCount, 0)));
    for (std::size_t i = 0; i < lists.size(); ++i) {
        const ImDrawList& source = *data.CmdLists[i];
        List& list = lists[i];
        list.owner = source._OwnerName ? source._OwnerName : "";
        list.bytes.reserve(
            static_cast<std::size_t>(source.VtxBuffer.size_in_bytes() + source.IdxBuffer.size_in_bytes()) +
            static_cast<std::size_t>(source.CmdBuffer.size()) * sizeof(ImDrawCmd));
        append(list.bytes, source.VtxBuffer.Data, static_cast<std::size_t>(source.VtxBuffer.size_in_bytes()));
        append(list.bytes, source.IdxBuffer.Data, static_cast<std::size_t>(source.IdxBuffer.size_in_bytes()));
        for (const ImDrawCmd& c : source.CmdBuffer) {
            appendCommand(list.bytes, c);
            if (c.UserCallback == ImDrawCallback_ResetRenderState)
                continue;
            const DamageRect drawn = drawnBy(data, source, c);
            list.bounds = unite(list.bounds, drawn);
            if (c.UserCallback || c.TextureId != fontTexture)
                list.content.push_back(drawn);
        }
    }
    return lists;
}

// Windows are matched by owner. One that appeared or went is damage where it is or was; one whose lists
// changed, where it was and is; the others only where they show content that changed. Windows that changed
// their order (one brought to the front) change what covers what: none is returned, for the whole frame.
std::optional<std::vector<DamageRect>> FrameDamage::changes(const std::vector<List>& lists,
                                                            std::uint64_t contentVersion) const {
    std::map<std::string_view, std::size_t> before;
    for (std::size_t i = 0; i < lists_.size(); ++i)
        if (!before.emplace(lists_[i].owner, i).second)
            return std::nullopt; // two lists of one owner cannot be told apart
    std::vector<bool> kept(lists_.size(), false);
    std::vector<DamageRect> rects;
    std::size_t next = 0; // lists that stay keep their order: each comes after the one before it
    for (const List& list : lists) {
        const auto old = before.find(list.owner);
        if (old == before.end()) {
            rects.push_back(list.bounds);
            continue;
        }
        if (old->second < next || kept[old->second])
            return std::nullopt;
        next = old->second + 1;
        kept[old->second] = true;
        const List& was = lists_[old->second];
        if (!sameBytes(was.bytes, list.bytes)) {
            rects.push_back(was.bounds);
            rects.push_back(list.bounds);
        } else if (contentVersion != contentVersion_) {
            rects.insert(rects.end(), list.content.begin(), list.content.end());
        }
    }
    for (std::size_t i = 0; i < lists_.size(); ++i)
        if (!kept[i])
            rects.push_back(lists_[i].bounds);
    return rects;
}

std::vector<DamageRect> FrameDamage::update(const ImDrawData& data, std::uint64_t contentVersion,
                                            ImTextureID fontTexture) {
    const DamageRect whole{0, 0, static_cast<int>(data.DisplaySize.x * data.FramebufferScale.x),
                           framebufferHeight(data)};
    std::vector<List> lists = describe(data, fontTexture);
    const bool sameDisplay =
        !lists_.empty() && data.DisplayPos.x == displayPos_.x && data.DisplayPos.y == displayPos_.y &&
        data.DisplaySize.x == displaySize_.x && data.DisplaySize.y == displaySize_.y &&
        data.FramebufferScale.x == framebufferScale_.x && data.FramebufferScale.y == framebufferScale_.y;
    std::optional<std::vector<DamageRect>> rects;
    if (sameDisplay)
        rects = changes(lists, contentVersion);
    // A scale that is not whole leaves clip rectangles unsnapped: a frame that changes is drawn whole.
    if (!rects || (!wholeScale(data) && !rects->empty()))
        rects = std::vector<DamageRect>{whole};
    lists_ = std::move(lists);
    displayPos_ = data.DisplayPos;
    displaySize_ = data.DisplaySize;
    framebufferScale_ = data.FramebufferScale;
    contentVersion_ = contentVersion;
    for (DamageRect& r : *rects)
        r = intersect(r, whole);
    return merged(std::move(*rects));
}

void snapClipRects(ImDrawData& data) {
    if (!wholeScale(data))
        return;
    for (int i = 0; i < data.CmdListsCount; ++i)
        for (ImDrawCmd& c : data.CmdLists[i]->CmdBuffer) {
            const DamageRect r = scissorOf(data, c.ClipRect);
            c.ClipRect = r.empty() ? ImVec4(0, 0, 0, 0) : clipOf(data, r);
        }
}

void drawWithin(ImDrawData& data, const DamageRect& rect) {
    std::vector<ImVec4> clips;
    for (int i = 0; i < data.CmdListsCount; ++i)
        for (ImDrawCmd& c : data.CmdLists[i]->CmdBuffer) {
            clips.push_back(c.ClipRect);
            const DamageRect cut = intersect(scissorOf(data, c.ClipRect), rect);
            c.ClipRect = cut.empty() ? ImVec4(0, 0, 0, 0) : clipOf(data, cut);
        }
    ImGui_ImplOpenGL3_RenderDrawData(&data);
    auto saved = clips.begin();
    for (int i = 0; i < data.CmdListsCount; ++i)
        for (ImDrawCmd& c : data.CmdLists[i]->CmdBuffer)
            c.ClipRect = *saved++;
}

} // namespace dc::ui
