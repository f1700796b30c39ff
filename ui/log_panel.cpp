#include "ui/panels.h"

#include <chrono>

namespace dc::ui {

namespace {

ImVec4 levelColor(LogLevel level) {
    switch (level) {
    case LogLevel::Error:
        return {1.0f, 0.45f, 0.35f, 1.0f};
    case LogLevel::Warning:
        return {1.0f, 0.8f, 0.3f, 1.0f};
    case LogLevel::Notice:
        return {0.55f, 0.9f, 0.55f, 1.0f};
    case LogLevel::Debug:
        return ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled);
    case LogLevel::Info:
        break;
    }
    return ImGui::GetStyleColorVec4(ImGuiCol_Text);
}

} // namespace

void drawLogPanel(const std::vector<LogEntry>& entries, LogPanelState& state, bool* open) {
    if (!ImGui::Begin(kLogTitle, open)) {
        ImGui::End();
        return;
    }
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 7.0f);
    ImGui::Combo("Level", &state.minLevel, "debug\0info\0notice\0warning\0error\0");
    ImGui::SameLine();
    state.filter.Draw("Filter", ImGui::GetFontSize() * 12.0f);
    ImGui::Separator();
    if (ImGui::BeginChild("##log", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar)) {
        for (const LogEntry& e : entries) {
            if (static_cast<int>(e.level) < state.minLevel || !state.filter.PassFilter(e.message.c_str()))
                continue;
            ImGui::TextColored(levelColor(e.level), "%-7s %s", toString(e.level), e.message.c_str());
        }
        // Follow new messages unless the user scrolled up to read.
        if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY())
            ImGui::SetScrollHereY(1.0f);
    }
    ImGui::EndChild();
    ImGui::End();
}

void drawToasts(const std::vector<LogEntry>& entries, float bottomMargin) {
    constexpr auto kShownFor = std::chrono::seconds(6);
    constexpr int kMaxToasts = 3;
    const auto now = std::chrono::steady_clock::now();
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    float y = vp->WorkPos.y + vp->WorkSize.y - bottomMargin - 8.0f;
    int shown = 0;
    for (auto it = entries.rbegin(); it != entries.rend() && shown < kMaxToasts; ++it) {
        if (it->level < LogLevel::Notice || now - it->time > kShownFor)
            continue;
        ImGui::SetNextWindowPos({vp->WorkPos.x + vp->WorkSize.x - 8.0f, y}, ImGuiCond_Always, {1.0f, 1.0f});
        ImGui::SetNextWindowBgAlpha(0.85f);
        const std::string id = kToastPrefix + std::to_string(it->id);
        constexpr ImGuiWindowFlags kFlags =
            ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
            ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
            ImGuiWindowFlags_NoInputs;
        if (ImGui::Begin(id.c_str(), nullptr, kFlags)) {
            ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
            ImGui::TextColored(levelColor(it->level), "%s", it->message.c_str());
            ImGui::PopTextWrapPos();
            y -= ImGui::GetWindowHeight() + 6.0f;
        }
        ImGui::End();
        ++shown;
    }
}

} // namespace dc::ui
