#include "ui/panels.h"

#include <cstdio>
#include <string>

namespace dc::ui {

namespace {

std::string format(const char* pattern, auto... values) {
    char text[256];
    std::snprintf(text, sizeof text, pattern, values...);
    return text;
}

// The parts of the line in order of importance: what the source is and does, then the frames, then the
// costliest stages while there is room for them.
std::vector<std::string> statusParts(const StatusLine& s) {
    const engine::FrameCounts& f = s.frames;
    std::vector<std::string> parts{
        s.source + " | " + s.state,
        format("device %.1f fps | shown %.1f fps | dropped %llu", f.deliveredPerSecond, f.shownPerSecond,
               static_cast<unsigned long long>(f.dropped)),
        format("points %llu, %s", static_cast<unsigned long long>(s.pointsDrawn), s.cloudPath.c_str())};
    if (!s.calibration.empty())
        parts.insert(parts.begin() + 1, s.calibration);
    if (s.latencyMs)
        parts.push_back(format("latency %.1f ms", *s.latencyMs));
    return parts;
}

} // namespace

float drawStatusBar(const StatusLine& s) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float height = ImGui::GetFrameHeightWithSpacing() + ImGui::GetStyle().WindowPadding.y;
    ImGui::SetNextWindowPos({viewport->WorkPos.x, viewport->WorkPos.y + viewport->WorkSize.y - height});
    ImGui::SetNextWindowSize({viewport->WorkSize.x, height});
    constexpr ImGuiWindowFlags kFlags =
        ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
        ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (ImGui::Begin("##status", nullptr, kFlags)) {
        // The message first when there is one: a source that fails must say so whatever else fits.
        const float right = ImGui::GetWindowContentRegionMax().x;
        bool first = true;
        const auto put = [&](const std::string& text, bool disabled, bool alert) {
            const std::string piece = first ? text : "| " + text;
            // Where the piece would start: beside the last one. A piece that does not fit whole is left out.
            const float start =
                ImGui::GetItemRectMax().x - ImGui::GetWindowPos().x + ImGui::GetStyle().ItemSpacing.x;
            if (!first && start + ImGui::CalcTextSize(piece.c_str()).x > right)
                return false;
            if (!first)
                ImGui::SameLine();
            first = false;
            if (alert)
                ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", piece.c_str());
            else if (disabled)
                ImGui::TextDisabled("%s", piece.c_str());
            else
                ImGui::TextUnformatted(piece.c_str());
            return true;
        };
        if (!s.recording.empty())
            put(s.recording, false, true);
        for (const std::string& part : statusParts(s))
            put(part, false, false);
        if (!s.message.empty())
            put(s.message, false, true);
        // Largest first, while they fit; the Stats panel lists every one.
        for (const auto& stage : s.stageMedians)
            if (!put(format("%s %.2f ms", stage.name.c_str(), stage.milliseconds), true, false))
                break;
    }
    ImGui::End();
    return height;
}

} // namespace dc::ui
