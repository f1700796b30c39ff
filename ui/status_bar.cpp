#include "ui/panels.h"

#include <string>

namespace dc::ui {

float drawStatusBar(const StatusLine& s) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float height = ImGui::GetFrameHeightWithSpacing() + ImGui::GetStyle().WindowPadding.y;
    ImGui::SetNextWindowPos({viewport->WorkPos.x, viewport->WorkPos.y + viewport->WorkSize.y - height});
    ImGui::SetNextWindowSize({viewport->WorkSize.x, height});
    constexpr ImGuiWindowFlags kFlags =
        ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
        ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (ImGui::Begin("##status", nullptr, kFlags)) {
        ImGui::Text("%s | %s | device %.1f fps | viewer %.1f fps | dropped %llu | points %llu",
                    s.source.c_str(), s.state.c_str(), s.deviceFps, s.viewerFps,
                    static_cast<unsigned long long>(s.framesDropped),
                    static_cast<unsigned long long>(s.pointsDrawn));
        if (s.latencyMs) {
            ImGui::SameLine();
            ImGui::Text("| latency %.1f ms", *s.latencyMs);
        }
        for (const auto& stage : s.stageMedians) {
            ImGui::SameLine();
            ImGui::TextDisabled("| %s %.2f ms", stage.name.c_str(), stage.milliseconds);
        }
        if (!s.message.empty()) {
            ImGui::SameLine();
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "| %s", s.message.c_str());
        }
    }
    ImGui::End();
    return height;
}

} // namespace dc::ui
