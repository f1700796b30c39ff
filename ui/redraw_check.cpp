#include "ui/redraw_check.h"

#include <utility>

namespace dc::ui {

namespace {

void append(std::vector<std::byte>& out, const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::byte*>(data);
    out.insert(out.end(), bytes, bytes + size);
}

template <class T> void appendValue(std::vector<std::byte>& out, const T& value) {
    append(out, &value, sizeof value);
}

// Every field the renderer reads, one by one: ImDrawCmd's padding is not part of the picture.
void appendCommand(std::vector<std::byte>& out, const ImDrawCmd& c) {
    appendValue(out, c.ClipRect);
    appendValue(out, c.TextureId);
    appendValue(out, c.VtxOffset);
    appendValue(out, c.IdxOffset);
    appendValue(out, c.ElemCount);
    appendValue(out, c.UserCallback);
    appendValue(out, c.UserCallbackData);
}

} // namespace

bool RedrawCheck::needed(const ImDrawData& data, std::uint64_t contentVersion) {
    next_.clear();
    appendValue(next_, contentVersion);
    appendValue(next_, data.DisplayPos);
    appendValue(next_, data.DisplaySize);
    appendValue(next_, data.FramebufferScale);
    for (int i = 0; i < data.CmdListsCount; ++i) {
        const ImDrawList& list = *data.CmdLists[i];
        appendValue(next_, list.VtxBuffer.Size);
        append(next_, list.VtxBuffer.Data, static_cast<std::size_t>(list.VtxBuffer.size_in_bytes()));
        appendValue(next_, list.IdxBuffer.Size);
        append(next_, list.IdxBuffer.Data, static_cast<std::size_t>(list.IdxBuffer.size_in_bytes()));
        appendValue(next_, list.CmdBuffer.Size);
        for (const ImDrawCmd& c : list.CmdBuffer)
            appendCommand(next_, c);
    }
    if (next_ == drawn_)
        return false;
    std::swap(next_, drawn_);
    return true;
}

} // namespace dc::ui
