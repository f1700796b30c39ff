#include "ui/panels.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <utility>

namespace dc::ui {

namespace {

// Puts the checkbox labelled `label` beside the last item when it fits there whole, else on a line of its
// own: a label cut at the panel's edge cannot be read.
void sameLineIfFits(const char* label) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const float need = ImGui::GetFrameHeight() + style.ItemInnerSpacing.x + ImGui::CalcTextSize(label).x;
    const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (right - (ImGui::GetItemRectMax().x + style.ItemSpacing.x) >= need)
        ImGui::SameLine();
}

bool confidenceSection(CloudSettings& cloud) {
    ImGui::TextUnformatted("Cloud confidence");
    int level = static_cast<int>(cloud.minConfidence);
    bool changed = ImGui::RadioButton("All [1]", &level, 0);
    changed |= ImGui::RadioButton("Medium and high [2]", &level, 1);
    changed |= ImGui::RadioButton("High only [3]", &level, 2);
    cloud.minConfidence = static_cast<frame::Confidence>(level);
    return changed;
}

bool viewSection(CloudSettings& cloud) {
    bool changed = ImGui::Checkbox("Auto-rotate [R]", &cloud.motion.enabled);
    changed |= ImGui::SliderFloat("Speed", &cloud.motion.speed, 0.0f, 4.0f, "%.2fx");
    changed |= ImGui::SliderFloat("Scale movement", &cloud.motion.scaleMovement, 0.0f, 2.0f, "%.2f");
    if (ImGui::Button("Reset view [V]")) {
        cloud.orbit = {};
        changed = true;
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("Drag to orbit, right-drag to pan, wheel to zoom, double-click to reset.");
    ImGui::PopStyleColor();
    int coloring = static_cast<int>(cloud.coloring);
    changed |= ImGui::Combo("Colour points by", &coloring, "camera\0depth (colormap)\0confidence\0");
    cloud.coloring = static_cast<render::PointColoring>(coloring);
    changed |= ImGui::SliderFloat("Point size", &cloud.pointSizePixels, 1.0f, 8.0f, "%.1f px");
    changed |= ImGui::SliderFloat("Near limit", &cloud.nearMeters, 0.0f, 2.0f, "%.2f m");
    return changed;
}

// How the cloud is drawn: the path (the one in use, and why, beside it) and the decimation with the
// factor and point count it gives.
bool drawingSection(CloudSettings& cloud, const ControlsContext& context) {
    int path = static_cast<int>(cloud.path);
    bool changed = ImGui::Combo("Cloud path", &path, "automatic\0GL points\0CPU splat\0");
    cloud.path = static_cast<CloudPathChoice>(path);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Drawing with %s.\nAutomatic draws on the CPU's cores when OpenGL renders in software.",
            context.cloudPath.c_str());
    char format[96];
    std::snprintf(format, sizeof format, "%s: %dx, %llu points", cloud.decimation == 0 ? "fit panel" : "%dx",
                  context.cloudDecimation, static_cast<unsigned long long>(context.cloudPoints));
    changed |= ImGui::SliderInt("Decimation", &cloud.decimation, 0, kMaxDecimation, format);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Each cell of NxN depth samples becomes its nearest point.\n"
                          "'fit panel' keeps at most one point per pixel of the cloud panel.");
    changed |= ImGui::Checkbox("Fill gaps", &cloud.fillGaps);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Points at least as wide as their sample on screen: no background between the\n"
                          "samples of a surface. Off: each sample is a point of the chosen size.");
    return changed;
}

// A toggle for a processing stage; disabled, with the reason as its tooltip, while this build lacks it.
bool stageToggle(const char* label, const char* stage, bool* value, bool available) {
    ImGui::BeginDisabled(!available);
    const bool changed = ImGui::Checkbox(label, value);
    ImGui::EndDisabled();
    if (!available && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Not available yet: this build has no %s stage.", stage);
    return changed && available;
}

bool depthSection(DepthRange& range, DepthView& view) {
    int colormap = static_cast<int>(range.colormap);
    bool changed = ImGui::Combo("Colormap", &colormap, "jet\0turbo\0viridis\0grayscale\0");
    range.colormap = static_cast<render::Colormap>(colormap);
    changed |= ImGui::Checkbox("Automatic range", &range.automatic);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Follow the 2nd to 98th depth percentile, smoothed over frames; off: the fixed range.");
    // Beside the range's switch where the panel is wide enough, and its opacity only while it is on: the
    // View group must still fit a 1280x720 window.
    sameLineIfFits("Colour overlay");
    changed |= ImGui::Checkbox("Colour overlay", &view.colourOverlay);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Lay the camera's colour, aligned to the depth, over the depth panel; depth the "
                          "colour camera does not see stays uncovered.");
    if (view.colourOverlay)
        changed |= ImGui::SliderFloat("Colour opacity", &view.overlayOpacity, 0.0f, 1.0f, "%.2f");
    ImGui::BeginDisabled(range.automatic);
    changed |= ImGui::DragFloatRange2("Depth range", &range.minMeters, &range.maxMeters, 0.01f, 0.0f, 100.0f,
                                      "%.2f m", "%.2f m", ImGuiSliderFlags_AlwaysClamp);
    ImGui::EndDisabled();
    return changed;
}

bool cameraSection(CameraView& camera) {
    bool changed = ImGui::Checkbox("Fill camera panel", &camera.fill);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Crop the image to fill the panel, as the sample's display transform does.");
    changed |= ImGui::Checkbox("Depth over camera", &camera.depthOverlay);
    ImGui::BeginDisabled(!camera.depthOverlay);
    changed |= ImGui::SliderFloat("Opacity", &camera.overlayOpacity, 0.0f, 1.0f, "%.2f");
    ImGui::EndDisabled();
    return changed;
}

void anchorsSection(const ControlsContext& context, ControlsResult& result) {
    ImGui::Text("Anchors: %zu", context.anchorCount);
    ImGui::SameLine();
    ImGui::BeginDisabled(context.anchorCount == 0);
    result.undoAnchor = ImGui::SmallButton("Undo [Z]");
    ImGui::SameLine();
    result.clearAnchors = ImGui::SmallButton("Clear");
    ImGui::EndDisabled();
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("Click the cloud to drop an anchor; two show their distance, three or more an area.");
    ImGui::PopStyleColor();
}

bool accumulateSection(AccumulateSettings& acc, const ControlsContext& context, ControlsResult& result) {
    ImGui::BeginDisabled(!context.hasPose);
    bool changed = ImGui::Checkbox("Accumulate", &acc.enabled);
    ImGui::EndDisabled();
    if (!context.hasPose && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Needs a source with camera poses (an ARKit capture, synthetic:motion).");
    if (!acc.enabled || !context.hasPose)
        return changed;
    ImGui::SameLine();
    result.clearAccumulation = ImGui::SmallButton("Clear points");
    changed |= ImGui::SliderInt("Budget", &acc.budgetThousands, 10, 4000, "%dk points");
    changed |= ImGui::SliderFloat("Voxel", &acc.voxelMillimeters, 0.5f, 50.0f, "%.1f mm",
                                  ImGuiSliderFlags_Logarithmic);
    ImGui::Text("%zu points held", context.accumulatedPoints);
    return changed;
}

bool smoothingControls(processing::SmoothingParams& p) {
    bool changed = ImGui::SliderFloat("Alpha", &p.alpha, 0.05f, 1.0f, "%.2f");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Weight of the newest depth: lower is smoother and slower to follow.");
    changed |=
        ImGui::SliderFloat("Jump", &p.jumpMeters, 0.005f, 1.0f, "%.3f m", ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A change larger than this restarts the average (motion, not noise).");
    changed |= ImGui::SliderInt("Hole frames", &p.holeFrames, 0, 30);
    return changed;
}

// The method list: the full guided filter, the fast one with its subsampling factor, the global smoother's
// real-time and quality modes.
int methodIndex(const processing::UpsamplingParams& p) {
    switch (p.method) {
    case processing::UpsamplingMethod::Full:
        return 0;
    case processing::UpsamplingMethod::Fast:
        return p.subsample == 2 ? 1 : p.subsample == 8 ? 3 : 2;
    case processing::UpsamplingMethod::Global:
        return 4;
    case processing::UpsamplingMethod::Quality:
        return 5;
    }
    return 2;
}

void setMethod(processing::UpsamplingParams& p, int index) {
    constexpr processing::UpsamplingMethod kMethods[] = {
        processing::UpsamplingMethod::Full,   processing::UpsamplingMethod::Fast,
        processing::UpsamplingMethod::Fast,   processing::UpsamplingMethod::Fast,
        processing::UpsamplingMethod::Global, processing::UpsamplingMethod::Quality};
    p.method = kMethods[std::clamp(index, 0, 5)];
    if (p.method == processing::UpsamplingMethod::Fast)
        p.subsample = index == 1 ? 2 : index == 3 ? 8 : 4;
}

bool guidedFilterControls(processing::UpsamplingParams& p) {
    bool changed = ImGui::SliderInt("Radius", &p.radiusPixels, 1, 32, "%d px");
    changed |= ImGui::SliderFloat("Epsilon", &p.epsilon, 1e-5f, 1e-1f, "%.5f", ImGuiSliderFlags_Logarithmic);
    changed |= ImGui::Checkbox("Edge-aware weights", &p.fitWeighted);
    return changed;
}

bool globalSmootherControls(processing::UpsamplingParams& p) {
    float noiseMillimeters = p.depthNoiseMeters * 1000.0f;
    bool changed = ImGui::SliderFloat("Depth noise", &noiseMillimeters, 0.5f, 50.0f, "%.1f mm",
                                      ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "The sensor's noise: steps well above it stay sharp, smaller differences are smoothed.");
    p.depthNoiseMeters = noiseMillimeters / 1000.0f;
    changed |=
        ImGui::SliderFloat("Smoothness", &p.smoothness, 0.1f, 10.0f, "%.2fx", ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Scales how far depth spreads along surfaces of one colour.");
    return changed;
}

bool upsamplingControls(processing::UpsamplingParams& p) {
    int method = methodIndex(p);
    bool changed = ImGui::Combo("Method", &method,
                                "full guided filter\0fast, s = 2\0fast, s = 4\0fast, s = 8\0"
                                "global smoother (real time)\0global smoother, quality\0");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The global smoother: colour- then depth-guided least squares, closest to the best "
                          "offline result; its quality mode takes hundreds of milliseconds per frame.");
    setMethod(p, method);
    int size = static_cast<int>(p.size);
    changed |= ImGui::Combo("Output", &size, "half camera size\0full camera size\0");
    p.size = static_cast<processing::UpsamplingSize>(size);
    const bool global =
        p.method == processing::UpsamplingMethod::Global || p.method == processing::UpsamplingMethod::Quality;
    changed |= global ? globalSmootherControls(p) : guidedFilterControls(p);
    return changed;
}

bool panelsSection(PanelVisibility& panels, bool infraredAvailable, ControlsResult& result) {
    // Two columns: the list stays short enough to fit under the View group at 1280x720.
    const float column = ImGui::GetWindowContentRegionMin().x +
                         0.5f * (ImGui::GetWindowContentRegionMax().x - ImGui::GetWindowContentRegionMin().x);
    const std::pair<const char*, bool*> toggles[] = {{kCloudTitle, &panels.cloud},
                                                     {kDepthTitle, &panels.depth},
                                                     {kConfidenceTitle, &panels.confidence},
                                                     {kCameraTitle, &panels.camera},
                                                     {kInfraredTitle, &panels.infrared},
                                                     {"Timeline [T]", &panels.timeline},
                                                     {"Stats [S]", &panels.stats},
                                                     {"Log [L]", &panels.log},
                                                     {"Source [O]", &panels.source},
                                                     {"Fog [F]", &panels.fog},
                                                     {"Aura [A]", &panels.aura},
                                                     {kQualityTitle, &panels.quality}};
    bool changed = false;
    for (std::size_t i = 0; i < std::size(toggles); ++i) {
        if (i % 2 == 1)
            ImGui::SameLine(column);
        const bool infrared = toggles[i].second == &panels.infrared;
        ImGui::BeginDisabled(infrared && !infraredAvailable);
        changed |= ImGui::Checkbox(toggles[i].first, toggles[i].second);
        ImGui::EndDisabled();
        if (infrared && !infraredAvailable && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("This source delivers no infrared image.");
        if (toggles[i].second == &panels.timeline && ImGui::IsItemHovered())
            ImGui::SetTooltip("The strip under the panels while the source is a recording.");
    }
    result.resetLayout = ImGui::Button("Reset layout");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The default panels in their default places for this window size.");
    return changed;
}

} // namespace

bool processingControls(processing::ProcessingSettings& p, const ControlsContext& context) {
    int source = static_cast<int>(p.depthSource);
    ImGui::TextUnformatted("Depth shown");
    ImGui::SameLine();
    bool changed = ImGui::RadioButton("raw", &source, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("smoothed", &source, 1);
    p.depthSource = static_cast<processing::DepthSource>(source);
    changed |= stageToggle("Temporal smoothing", "smoothing", &p.smoothing, context.smoothingAvailable);
    if (p.smoothing && context.smoothingAvailable)
        changed |= smoothingControls(p.smoothingParams);
    changed |= stageToggle("Guided upsampling", "upsampling", &p.upsampling, context.upsamplingAvailable);
    if (p.upsampling && context.upsamplingAvailable)
        changed |= upsamplingControls(p.upsamplingParams);
    return changed;
}

ControlsResult drawControlsPanel(Settings& settings, const ControlsContext& context, bool* open) {
    ControlsResult result;
    if (!ImGui::Begin(kControlsTitle, open)) {
        ImGui::End();
        return result;
    }
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 8.5f); // room for the longest label
    // Grouped so that at 1280x720 the common groups (View, Panels) fit without scrolling; the others open
    // with a click and ImGui remembers which are open.
    bool changed = false;
    if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
        changed |= confidenceSection(settings.cloud);
        changed |= viewSection(settings.cloud);
        changed |= depthSection(settings.depthRange, settings.depthView);
    }
    if (ImGui::CollapsingHeader("Panels", ImGuiTreeNodeFlags_DefaultOpen))
        changed |= panelsSection(settings.panels, context.infraredAvailable, result);
    if (ImGui::CollapsingHeader("Measure", ImGuiTreeNodeFlags_DefaultOpen)) {
        anchorsSection(context, result);
        changed |= accumulateSection(settings.accumulate, context, result);
    }
    if (ImGui::CollapsingHeader("Camera panel"))
        changed |= cameraSection(settings.camera);
    if (ImGui::CollapsingHeader("Processing")) {
        changed |= processingControls(settings.processing, context);
        changed |= drawingSection(settings.cloud, context);
    }
    if (context.recordState && ImGui::CollapsingHeader("Record")) {
        result.toggleRecording = drawRecordControls(context.record, settings.record, *context.recordState);
        result.snapshot = ImGui::Button("Snapshot [P]");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Every panel's image at full resolution as PNG and the cloud as PLY, into "
                              "depthcloud-snapshots/.");
    }
    ImGui::PopItemWidth();
    ImGui::End();
    if (changed)
        sanitize(settings);
    result.changed = changed;
    return result;
}

bool handleShortcuts(Settings& settings) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput)
        return false;
    // Debian's ImGui 1.86 indexes keys by the platform's key codes; GLFW's codes for letters and digits
    // are their ASCII values.
    bool fired = false;
    if (ImGui::IsKeyPressed('R', false)) {
        settings.cloud.motion.enabled = !settings.cloud.motion.enabled;
        fired = true;
    }
    for (int level = 0; level < 3; ++level) {
        if (ImGui::IsKeyPressed('1' + level, false)) {
            settings.cloud.minConfidence = static_cast<frame::Confidence>(level);
            fired = true;
        }
    }
    if (ImGui::IsKeyPressed('V', false)) {
        settings.cloud.orbit = {};
        fired = true;
    }
    const std::pair<int, bool*> panelKeys[] = {
        {'C', &settings.panels.controls}, {'S', &settings.panels.stats},  {'L', &settings.panels.log},
        {'T', &settings.panels.timeline}, {'O', &settings.panels.source}, {'F', &settings.panels.fog},
        {'A', &settings.panels.aura}};
    for (const auto& [key, shown] : panelKeys) {
        if (ImGui::IsKeyPressed(key, false)) {
            *shown = !*shown;
            fired = true;
        }
    }
    return fired;
}

} // namespace dc::ui
