#include "ui/panels.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace dc::ui {

namespace {

// What each figure means, as the README defines it (Intel's Depth Quality Tool where it has the figure).
constexpr const char* kFillHelp =
    "Valid samples / samples in the region. The rest, by cause: no measurement, "
    "outside [near, far], below the confidence, flying pixel.";
constexpr const char* kDistanceHelp = "Where the robust plane fit crosses the optical axis, mm.";
constexpr const char* kAngleHelp =
    "Angle between the plane's normal and the optical axis (0: facing the camera).";
constexpr const char* kRmsHelp =
    "Perpendicular RMS of the inliers to the robust plane (RANSAC/LMedS, then least "
    "squares), mm and % of the distance.";
constexpr const char* kInlierHelp =
    "Samples within the inlier threshold of the robust plane / valid samples.";
constexpr const char* kDqtHelp =
    "Intel DQT's plane-fit RMS: least squares through every valid sample, 0.5 % of "
    "the residuals trimmed at each end, mm.";
constexpr const char* kZHelp = "DQT's Z accuracy: (distance - ground truth) / ground truth, %.";
constexpr const char* kSubpixelHelp = "DQT's subpixel RMS: the plane-fit error as disparity, pixels.";
constexpr const char* kExpectedHelp =
    "The stereo model's noise at this distance, z^2 sd / (f B), for the design subpixel accuracy sd: "
    "a plane-fit RMS well above it at every distance is a calibration fault, not the design.";
constexpr const char* kTemporalHelp =
    "Each pixel's standard deviation over the window, median over the pixels "
    "valid in every frame of it, mm.";
constexpr const char* kSpatialHelp = "Median over the window of each frame's plane-fit RMS, mm.";

// One figure: its name with a (?) that defines it, and its value.
void row(const char* name, const std::string& value, const char* help) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(name);
    ImGui::SameLine();
    ImGui::TextDisabled("(?)");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%s", help);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(value.c_str());
}

std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

// The preset buttons (the one in use marked) and the rectangle drawn on the depth panel.
bool drawRegion(const processing::ShownQuality* quality, QualitySettings& s) {
    bool changed = false;
    ImGui::TextUnformatted("Region");
    for (const int percent : kQualityRoiPresets) {
        ImGui::SameLine();
        ImGui::PushID(percent);
        const std::string label = std::to_string(percent) + " %";
        const bool current = s.roiPercent == percent;
        if (current)
            ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
        if (ImGui::Button(label.c_str())) {
            s.roiPercent = percent;
            changed = true;
        }
        if (current)
            ImGui::PopStyleColor();
        ImGui::PopID();
    }
    if (quality)
        ImGui::TextDisabled("%s %d,%d %dx%d px (drag on Depth to draw one)",
                            s.roiPercent > 0 ? "centred" : "drawn", quality->roi.x, quality->roi.y,
                            quality->roi.width, quality->roi.height);
    return changed;
}

void drawFigures(const processing::ShownQuality& q) {
    ImGui::Text("Frame %llu", static_cast<unsigned long long>(q.sequence));
    if (!q.figures) {
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", q.error.c_str());
        return;
    }
    const processing::FillBreakdown& f = q.figures->fill;
    if (!ImGui::BeginTable("##figures", 2, ImGuiTableFlags_RowBg))
        return;
    row("Fill rate", format("%.1f %%", 100.0 * f.fillRate()), kFillHelp);
    row("  no measurement", format("%.1f %%", 100.0 * f.fraction(f.noMeasurement)), kFillHelp);
    row("  out of range", format("%.1f %%", 100.0 * f.fraction(f.outOfRange)), kFillHelp);
    row("  low confidence", format("%.1f %%", 100.0 * f.fraction(f.lowConfidence)), kFillHelp);
    row("  flying pixels", format("%.1f %%", 100.0 * f.fraction(f.flyingPixel)), kFillHelp);
    if (const auto& p = q.figures->plane) {
        row("Distance", format("%.1f mm", p->distanceMm), kDistanceHelp);
        row("Angle", format("%.2f deg", p->angleDeg), kAngleHelp);
        row("Plane-fit RMS",
            format("%.2f mm", p->planeFitRmsMm) + format(" (%.3f %%)", p->planeFitRmsPercent), kRmsHelp);
        row("Inliers", format("%.1f %%", 100.0 * p->inlierFraction), kInlierHelp);
        row("DQT plane-fit RMS", format("%.2f mm", p->dqtPlaneFitRmsMm), kDqtHelp);
        row("Z accuracy", p->zAccuracyPercent ? format("%.2f %%", *p->zAccuracyPercent) : "enter a truth",
            kZHelp);
        if (p->subpixelRms)
            row("Subpixel RMS", format("%.3f px", *p->subpixelRms), kSubpixelHelp);
        if (p->expectedNoiseMm)
            row("Expected noise", format("%.2f mm", *p->expectedNoiseMm), kExpectedHelp);
    }
    row("Temporal noise", q.temporalNoiseMm ? format("%.2f mm", *q.temporalNoiseMm) : "-", kTemporalHelp);
    row("Spatial noise", q.spatialNoiseMm ? format("%.2f mm", *q.spatialNoiseMm) : "-", kSpatialHelp);
    ImGui::EndTable();
    ImGui::TextDisabled("noise over %zu of %zu frames", q.windowFilled, q.windowFrames);
    if (!q.figures->plane)
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "plane: %s", q.figures->planeError.c_str());
    if (!q.noiseError.empty())
        ImGui::TextDisabled("noise: %s", q.noiseError.c_str());
}

// One figure of the kept frames over time, the figure chosen beside it.
void drawPlot(QualityPanelState& state) {
    ImGui::SetNextItemWidth(150.0f);
    if (ImGui::BeginCombo("##plotted", exporting::toString(state.plotted))) {
        for (const exporting::QualityFigure figure : exporting::kQualityFigures)
            if (ImGui::Selectable(exporting::toString(figure), figure == state.plotted))
                state.plotted = figure;
        ImGui::EndCombo();
    }
    const std::vector<double> series = exporting::qualitySeries(state.log, state.plotted);
    if (series.empty()) {
        ImGui::TextDisabled("not measured in the kept frames");
        return;
    }
    const auto [low, high] = std::minmax_element(series.begin(), series.end());
    ImGui::SameLine();
    ImGui::TextDisabled("%.2f .. %.2f", *low, *high);
    // A plot wider than its pixels would only average: the last frames that fit, one pixel each.
    const std::size_t shown =
        std::min(series.size(), static_cast<std::size_t>(ImGui::GetContentRegionAvail().x));
    std::vector<float> values(series.end() - static_cast<std::ptrdiff_t>(shown), series.end());
    ImGui::PlotLines("##over time", values.data(), static_cast<int>(values.size()), 0, nullptr,
                     static_cast<float>(*low), static_cast<float>(*high), ImVec2(-1.0f, 60.0f));
}

// The figures of every frame shown since the source opened (or the last Clear): plotted, saved on request.
void drawLog(QualityPanelState& state, QualityPanelResult& result) {
    ImGui::Separator();
    const std::size_t frames = state.log.rows().size();
    if (frames > 0)
        drawPlot(state);
    ImGui::Text("%zu frames kept", frames);
    ImGui::SameLine();
    ImGui::BeginDisabled(frames == 0);
    result.save = ImGui::Button("Save CSV + JSON");
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Every kept frame's figures, with the source, region and settings, into a new "
                          "folder under depthcloud-snapshots/.");
    ImGui::SameLine();
    result.clear = ImGui::Button("Clear");
    ImGui::EndDisabled();
    if (!state.savedTo.empty())
        ImGui::TextDisabled("saved to %s", state.savedTo.c_str());
}

bool drawSettings(QualitySettings& s) {
    if (!ImGui::CollapsingHeader("Settings"))
        return false;
    bool changed = ImGui::SliderInt("window frames", &s.windowFrames, 2, 300);
    changed |= ImGui::InputFloat("ground truth mm", &s.groundTruthMm, 10.0f, 100.0f, "%.1f");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The target's true distance, for the Z accuracy; 0: none.");
    changed |= ImGui::InputFloat("stereo baseline mm", &s.baselineMm, 1.0f, 10.0f, "%.1f");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "A stereo camera's baseline, for the subpixel RMS and the expected noise; 0: none.");
    changed |= ImGui::InputFloat("design subpixel px", &s.designSubpixelRms, 0.01f, 0.05f, "%.3f");
    changed |= ImGui::DragFloatRange2("range m", &s.nearMeters, &s.farMeters, 0.01f, 0.0f, 100.0f, "%.2f");
    changed |= ImGui::InputFloat("flying threshold mm", &s.flyingThresholdMm, 1.0f, 10.0f, "%.0f");
    if (changed)
        sanitize(s);
    return changed;
}

} // namespace

QualityPanelResult drawQualityPanel(const processing::ShownQuality* quality, QualitySettings& settings,
                                    QualityPanelState& state, bool* open) {
    QualityPanelResult result;
    if (!ImGui::Begin(kQualityTitle, open)) {
        ImGui::End();
        return result;
    }
    result.settingsChanged = drawRegion(quality, settings);
    ImGui::Separator();
    if (quality)
        drawFigures(*quality);
    else
        ImGui::TextDisabled("No depth measured yet.");
    drawLog(state, result);
    result.settingsChanged |= drawSettings(settings);
    ImGui::End();
    return result;
}

} // namespace dc::ui
