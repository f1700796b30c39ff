#include "ui/panels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace dc::ui {

namespace {

double secondsOf(std::int64_t ns, std::int64_t originNs) {
    return static_cast<double>(ns - originNs) * 1e-9;
}

void transport(const devices::replay::ReplayStatus& s, TimelineActions& a) {
    if (ImGui::Button("|<"))
        a.seekIndex = 0;
    ImGui::SameLine();
    if (ImGui::Button("<"))
        a.step = -1;
    ImGui::SameLine();
    if (ImGui::Button(s.playing ? "Pause [Space]" : "Play [Space]"))
        a.play = !s.playing;
    ImGui::SameLine();
    if (ImGui::Button(">"))
        a.step = 1;
    ImGui::SameLine();
    if (ImGui::Button(">|"))
        a.seekIndex = s.count > 0 ? s.count - 1 : 0;
    ImGui::SameLine();
    bool loop = s.loop;
    if (ImGui::Checkbox("Loop", &loop))
        a.loop = loop;
    ImGui::SameLine();
    float speed = static_cast<float>(s.speed);
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 8.0f);
    if (ImGui::SliderFloat("Speed", &speed, 0.25f, 4.0f, "x%.2f", ImGuiSliderFlags_Logarithmic))
        a.speed = speed;
}

// Returns the scrubber's left and right edges on screen, for the rows under it.
std::pair<float, float> scrubber(const devices::replay::ReplayStatus& s, TimelineActions& a) {
    int index = static_cast<int>(s.index);
    const int last = std::max(0, static_cast<int>(s.count) - 1);
    ImGui::SetNextItemWidth(-1.0f);
    char label[96];
    std::snprintf(label, sizeof label, "frame %d / %d  %.3f s", index, last,
                  secondsOf(s.timestampNs, s.firstTimestampNs));
    if (ImGui::SliderInt("##frame", &index, 0, last, label, ImGuiSliderFlags_AlwaysClamp))
        a.seekIndex = static_cast<std::size_t>(index);
    return {ImGui::GetItemRectMin().x, ImGui::GetItemRectMax().x};
}

// Where the scrubber's grab is centred at `place` (0 its first frame, 1 its last): ImGui's integer slider
// keeps its grab 2 px inside the frame and one step wide, GrabMinSize at least.
float scrubberX(double place, std::pair<float, float> edges, std::size_t frames) {
    constexpr float kGrabPadding = 2.0f;
    const float slider = edges.second - edges.first - 2.0f * kGrabPadding;
    const float step = slider / static_cast<float>(std::max<std::size_t>(frames, 1));
    const float grab = std::min(std::max(step, ImGui::GetStyle().GrabMinSize), slider);
    return edges.first + kGrabPadding + 0.5f * grab + static_cast<float>(place) * (slider - grab);
}

// The row's label: which source, and the frame it shows or why it has no ticks.
std::string rowLabel(const TimelineSourceRow& row) {
    if (!row.note.empty())
        return row.name + ": " + row.note;
    if (!row.shown)
        return row.name + ": no frame yet";
    const std::size_t shown = *row.shown;
    const bool placed = shown >= row.places.first && shown - row.places.first < row.places.positions.size();
    return row.name + ": frame " + std::to_string(shown) + (placed ? "" : " (outside this replay)");
}

// One thin row under the scrubber: a tick at each of the source's frames, one per pixel at most, the frame
// it shows taller and bright, its name and frame over the left end.
void sourceRow(const TimelineSourceRow& row, std::pair<float, float> edges, std::size_t mainFrames) {
    const float height = ImGui::GetTextLineHeight();
    const ImVec2 top = ImGui::GetCursorScreenPos();
    ImGui::Dummy(ImVec2(edges.second - top.x, height));
    const ImVec2 below = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled({edges.first, top.y}, {edges.second, top.y + height},
                        ImGui::GetColorU32(ImGuiCol_FrameBg));
    const ImU32 tick = ImGui::GetColorU32(ImGuiCol_PlotLines);
    float lastX = -1.0f;
    for (const double place : row.places.positions) {
        const float x = std::round(scrubberX(place, edges, mainFrames));
        if (x != lastX)
            draw->AddLine({x, top.y + 0.4f * height}, {x, top.y + height}, tick);
        lastX = x;
    }
    if (row.shown && *row.shown >= row.places.first &&
        *row.shown - row.places.first < row.places.positions.size()) {
        const float x = scrubberX(row.places.positions[*row.shown - row.places.first], edges, mainFrames);
        draw->AddLine({x, top.y}, {x, top.y + height}, IM_COL32(255, 200, 60, 255), 3.0f);
    }
    const std::string label = rowLabel(row);
    const ImVec2 text = ImGui::CalcTextSize(label.c_str());
    const ImVec2 at{edges.first + ImGui::GetStyle().FramePadding.x, top.y};
    draw->AddRectFilled(at, {at.x + text.x, at.y + height}, ImGui::GetColorU32(ImGuiCol_WindowBg, 0.8f));
    ImGui::SetCursorScreenPos(at);
    ImGui::TextUnformatted(label.c_str());
    ImGui::SetCursorScreenPos(below);
}

void rangeAndExport(const TimelineView& v, TimelinePanelState& state, TimelineActions& a) {
    if (ImGui::SmallButton("Range start"))
        state.rangeStart = v.status.index;
    ImGui::SameLine();
    if (ImGui::SmallButton("Range end"))
        state.rangeEnd = v.status.index + 1;
    ImGui::SameLine();
    if (ImGui::SmallButton("Whole"))
        state.rangeStart = state.rangeEnd = 0;
    ImGui::SameLine();
    const std::size_t end = state.rangeEnd > 0 ? state.rangeEnd : v.status.count;
    ImGui::Text("range %zu:%zu (%zu frames)", state.rangeStart, end,
                end > state.rangeStart ? end - state.rangeStart : 0);
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6.0f);
    ImGui::Combo("##format", &state.format, "PLY\0Stray\0PNG16\0");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 14.0f);
    ImGui::InputText("##out", state.outDirectory.data(), state.outDirectory.size());
    ImGui::SameLine();
    if (v.exportTotal > 0 || v.exporting) {
        const float fraction = v.exportTotal > 0 ? static_cast<float>(v.exportDone) / v.exportTotal : 0.0f;
        ImGui::ProgressBar(fraction, ImVec2(ImGui::GetFontSize() * 8.0f, 0.0f));
        ImGui::SameLine();
    }
    if (v.exporting) {
        a.cancelExport = ImGui::Button("Cancel");
    } else if (ImGui::Button("Export range")) {
        a.exportRange = true;
    }
}

} // namespace

TimelineActions drawTimelinePanel(const TimelineView& view, TimelinePanelState& state, bool* open,
                                  ImGuiWindowFlags flags) {
    TimelineActions actions;
    if (!ImGui::Begin(kTimelineTitle, open, flags)) {
        ImGui::End();
        return actions;
    }
    transport(view.status, actions);
    const std::pair<float, float> edges = scrubber(view.status, actions);
    for (const TimelineSourceRow& row : view.sources)
        sourceRow(row, edges, view.status.count);
    if (view.status.framesSkipped > 0)
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%llu damaged frames skipped: %s",
                           static_cast<unsigned long long>(view.status.framesSkipped),
                           view.status.lastProblem.c_str());
    rangeAndExport(view, state, actions);
    ImGui::End();
    return actions;
}

bool drawRecordControls(const engine::RecordingStatus& view, RecordSettings& settings,
                        RecordPanelState& state) {
    if (view.recording)
        ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.7f, 0.15f, 0.15f, 1.0f));
    const std::string label = std::string(view.recording ? "Stop" : "Record") + kRecordButtonId;
    const bool toggle = ImGui::Button(label.c_str(), ImVec2(ImGui::GetFontSize() * 5.0f, 0.0f));
    if (view.recording)
        ImGui::PopStyleColor();
    ImGui::SameLine();
    if (view.recording) {
        const std::string name = std::filesystem::path(view.path).filename().string();
        ImGui::Text("%s: %llu frames, %llu dropped, %.1f MB", name.c_str(),
                    static_cast<unsigned long long>(view.frames),
                    static_cast<unsigned long long>(view.dropped),
                    static_cast<double>(view.bytesWritten) / 1e6);
    } else {
        if (!state.editing)
            std::snprintf(state.directory.data(), state.directory.size(), "%s", settings.directory.c_str());
        ImGui::SetNextItemWidth(-1.0f);
        if (ImGui::InputTextWithHint("##recordDirectory", "folder", state.directory.data(),
                                     state.directory.size()))
            settings.directory = state.directory.data();
        state.editing = ImGui::IsItemActive();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Takes are numbered in this folder: depthcloud-recording-001.dcrec, -002, ...");
    }
    // What a take stores is fixed once it starts.
    ImGui::BeginDisabled(view.recording);
    int color = settings.jpegColor ? 0 : 1;
    if (ImGui::Combo("camera image", &color, "JPEG\0as captured (raw)\0"))
        settings.jpegColor = color == 0;
    if (settings.jpegColor)
        ImGui::SliderInt("JPEG quality", &settings.jpegQuality, 1, 100);
    ImGui::EndDisabled();
    return toggle;
}

} // namespace dc::ui
