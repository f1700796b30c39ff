#include "ui/panels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
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
constexpr const char* kAlignmentHelp =
    "Colour registered onto the depth; the median distance from each depth silhouette pixel (the nearer "
    "side of a depth jump) to the nearest colour edge, px and mm at its depth, and the share of silhouette "
    "pixels with a colour edge within 10 px. Turn it on in Settings.";

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

// A shortfall's row: its cause's colour on the panels beside its name.
void causeRow(const char* name, processing::SampleCause cause, double fraction) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    const auto rgb = processing::causeColour(cause);
    ImGui::ColorButton(name, ImVec4(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, 1.0f),
                       ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoPicker,
                       ImVec2(ImGui::GetTextLineHeight(), ImGui::GetTextLineHeight()));
    ImGui::SameLine();
    ImGui::TextUnformatted(name);
    ImGui::TableNextColumn();
    ImGui::Text("%.1f %%", 100.0 * fraction);
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
            s.polygon.clear();
            changed = true;
        }
        if (current)
            ImGui::PopStyleColor();
        ImGui::PopID();
    }
    changed |= ImGui::Checkbox("Causes on the panels", &s.causeOverlay);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The region's missing samples in their causes' colours on the image panels.");
    if (quality && !quality->polygon.empty())
        ImGui::TextDisabled("polygon, %zu vertices, %zu samples (Shift-drag on Depth to draw one)",
                            quality->polygon.size(),
                            quality->figures ? quality->figures->fill.roiSamples : 0);
    else if (quality)
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
    using processing::SampleCause;
    causeRow("no measurement", SampleCause::NoMeasurement, f.fraction(f.noMeasurement));
    causeRow("out of range", SampleCause::OutOfRange, f.fraction(f.outOfRange));
    causeRow("low confidence", SampleCause::LowConfidence, f.fraction(f.lowConfidence));
    causeRow("flying pixels", SampleCause::FlyingPixel, f.fraction(f.flyingPixel));
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
    if (const auto& a = q.alignment)
        row("Colour alignment",
            format("%.2f px", a->medianPx) + format(" (%.1f mm)", a->medianMm) +
                format(", %.0f %% matched", 100.0 * a->matchedFraction()),
            kAlignmentHelp);
    else
        row("Colour alignment", q.alignmentError.empty() ? "off" : "-", kAlignmentHelp);
    ImGui::EndTable();
    ImGui::TextDisabled("noise over %zu of %zu frames", q.windowFilled, q.windowFrames);
    if (!q.figures->plane)
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "plane: %s", q.figures->planeError.c_str());
    if (!q.noiseError.empty())
        ImGui::TextDisabled("noise: %s", q.noiseError.c_str());
    if (!q.alignmentError.empty())
        ImGui::TextDisabled("alignment: %s", q.alignmentError.c_str());
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

// Where a distance step's point lies in the plot's frame.
struct DistanceAxes {
    ImVec2 min, max;
    double nearMm, farMm, topMm;
    ImVec2 at(double distanceMm, double valueMm) const {
        const double fx = farMm > nearMm ? (distanceMm - nearMm) / (farMm - nearMm) : 0.5;
        const double fy = topMm > 0.0 ? valueMm / topMm : 0.0;
        return {min.x + static_cast<float>(fx) * (max.x - min.x),
                max.y - static_cast<float>(fy) * (max.y - min.y)};
    }
};

// The plane-fit RMS of the kept frames against their distance (dots, each a step's median) with the stereo
// model's expected noise (a line) where a baseline is set: a camera at its design noise follows the line,
// a calibration fault sits above it at every distance.
void drawNoiseOverDistance(const exporting::QualityLog& log) {
    constexpr int kSteps = 48;
    constexpr double kMinSpan = 1.1;
    const std::vector<exporting::NoiseAtDistance> steps = exporting::noiseOverDistance(log, kSteps);
    // A camera held still measures one distance, give or take its noise: there is no curve to draw.
    if (steps.size() < 2 || steps.back().distanceMm < kMinSpan * steps.front().distanceMm)
        return;
    double top = 0.0;
    for (const auto& s : steps)
        top = std::max({top, s.planeFitRmsMm, s.expectedNoiseMm.value_or(0.0)});
    ImGui::TextDisabled("RMS over distance: %.0f .. %.0f mm, up to %.2f mm", steps.front().distanceMm,
                        steps.back().distanceMm, top);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 size(std::max(ImGui::GetContentRegionAvail().x, 50.0f), 70.0f);
    ImGui::InvisibleButton("##over distance", size);
    const DistanceAxes axes{origin,
                            {origin.x + size.x, origin.y + size.y},
                            steps.front().distanceMm,
                            steps.back().distanceMm,
                            top * 1.1};
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(axes.min, axes.max, ImGui::GetColorU32(ImGuiCol_FrameBg));
    const auto rgb = processing::causeColour(processing::SampleCause::OutOfRange);
    const ImU32 expectedColour = IM_COL32(rgb[0], rgb[1], rgb[2], 255);
    for (std::size_t i = 1; i < steps.size(); ++i) {
        if (steps[i - 1].expectedNoiseMm && steps[i].expectedNoiseMm)
            draw->AddLine(axes.at(steps[i - 1].distanceMm, *steps[i - 1].expectedNoiseMm),
                          axes.at(steps[i].distanceMm, *steps[i].expectedNoiseMm), expectedColour, 1.5f);
    }
    for (const auto& s : steps)
        draw->AddCircleFilled(axes.at(s.distanceMm, s.planeFitRmsMm), 2.5f, IM_COL32(255, 255, 255, 255));
    if (!ImGui::IsItemHovered())
        return;
    // The step nearest the mouse along the distance axis, in words.
    const float mouse = ImGui::GetIO().MousePos.x;
    const auto nearest = std::min_element(steps.begin(), steps.end(), [&](const auto& a, const auto& b) {
        return std::abs(axes.at(a.distanceMm, 0.0).x - mouse) <
               std::abs(axes.at(b.distanceMm, 0.0).x - mouse);
    });
    if (nearest->expectedNoiseMm)
        ImGui::SetTooltip("%.0f mm: plane-fit RMS %.2f mm, expected %.2f mm (%zu frames)",
                          nearest->distanceMm, nearest->planeFitRmsMm, *nearest->expectedNoiseMm,
                          nearest->frames);
    else
        ImGui::SetTooltip("%.0f mm: plane-fit RMS %.2f mm (%zu frames; a stereo baseline gives the expected)",
                          nearest->distanceMm, nearest->planeFitRmsMm, nearest->frames);
}

// The map's colours from its low to its high end, with both values and the unit.
void drawMapLegend(const processing::QualityMapImage& map) {
    constexpr int kSegments = 16;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = ImGui::GetTextLineHeight() * 0.6f;
    const auto colourAt = [&](int i) {
        const auto rgb = processing::mapColour(map.kind, static_cast<float>(i) / kSegments);
        return IM_COL32(rgb[0], rgb[1], rgb[2], 255);
    };
    for (int i = 0; i < kSegments; ++i) {
        const float x0 = p.x + width * static_cast<float>(i) / kSegments;
        const float x1 = p.x + width * static_cast<float>(i + 1) / kSegments;
        draw->AddRectFilledMultiColor({x0, p.y}, {x1, p.y + height}, colourAt(i), colourAt(i + 1),
                                      colourAt(i + 1), colourAt(i));
    }
    ImGui::Dummy({width, height});
    const char* unit = processing::unitOf(map.kind);
    ImGui::Text("%.2f %s", map.low, unit);
    char high[32];
    std::snprintf(high, sizeof high, "%.2f %s", map.high, unit);
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(high).x));
    ImGui::TextUnformatted(high);
}

// The chosen per-pixel map of the region, fitted to the panel's width, with its legend; the pixel under the
// mouse is read out.
std::optional<QualityMapHover> drawMap(const processing::ShownQuality* quality, QualitySettings& s,
                                       const PanelImage& image, bool& changed) {
    ImGui::SetNextItemWidth(180.0f);
    if (ImGui::BeginCombo("Map",
                          processing::toString(processing::kQualityMaps[static_cast<std::size_t>(s.map)]))) {
        for (int i = 0; i < static_cast<int>(std::size(processing::kQualityMaps)); ++i) {
            if (ImGui::Selectable(processing::toString(processing::kQualityMaps[static_cast<std::size_t>(i)]),
                                  i == s.map)) {
                changed |= s.map != i;
                s.map = i;
            }
        }
        ImGui::EndCombo();
    }
    if (s.map == 0 || !quality || !quality->map || image.empty()) {
        if (s.map != 0)
            ImGui::TextDisabled("no map yet (a residual needs a plane fit)");
        return std::nullopt;
    }
    const processing::QualityMapImage& map = *quality->map;
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = std::min(width * static_cast<float>(map.values.height) / map.values.width, 240.0f);
    const float shownWidth = height * static_cast<float>(map.values.width) / map.values.height;
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image.textureId)),
                 {shownWidth, height});
    const bool hovered = ImGui::IsItemHovered();
    drawMapLegend(map);
    if (!hovered)
        return std::nullopt;
    const ImVec2 m = ImGui::GetIO().MousePos;
    QualityMapHover hover;
    hover.x = std::clamp(static_cast<int>((m.x - origin.x) / shownWidth * map.values.width), 0,
                         map.values.width - 1);
    hover.y =
        std::clamp(static_cast<int>((m.y - origin.y) / height * map.values.height), 0, map.values.height - 1);
    hover.value = map.values.at(hover.x, hover.y);
    if (std::isfinite(hover.value))
        ImGui::SetTooltip("%d,%d: %.3f %s", hover.x, hover.y, hover.value, processing::unitOf(map.kind));
    else
        ImGui::SetTooltip("%d,%d: no value", hover.x, hover.y);
    return hover;
}

// The figures of every frame shown since the source opened (or the last Clear): plotted, saved on request.
void drawLog(QualityPanelState& state, QualityPanelResult& result) {
    ImGui::Separator();
    const std::size_t frames = state.log.rows().size();
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
    if (frames > 0) {
        drawPlot(state);
        drawNoiseOverDistance(state.log);
    }
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
    changed |= ImGui::Checkbox("colour-to-depth alignment", &s.alignment);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Registers the camera's colour onto the depth every frame: off unless you need it.");
    if (changed)
        sanitize(s);
    return changed;
}

} // namespace

QualityPanelResult drawQualityPanel(const processing::ShownQuality* quality, QualitySettings& settings,
                                    QualityPanelState& state, const PanelImage& map, bool* open) {
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
    ImGui::Separator();
    bool mapChanged = false;
    result.mapHover = drawMap(quality, settings, map, mapChanged);
    result.settingsChanged |= mapChanged;
    result.settingsChanged |= drawSettings(settings);
    ImGui::End();
    return result;
}

} // namespace dc::ui
