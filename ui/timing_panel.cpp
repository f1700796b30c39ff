// The Timing panel: where a stutter comes from. Per stream the intervals between frames (a steady camera
// is one bar, jitter widens it, a lost frame is a bar at twice the period) and what its timestamps mark;
// the latency from arrival, and from the sensor where its clock is this machine's, to the screen, with
// the parts it is made of; every frame that did not reach the screen, counted where it was lost; and, with
// several sources open, how far each further source's frames are from the main source's in time.

#include "ui/panels.h"

#include <imgui.h>

#include <cfloat>
#include <cstdio>

namespace dc::ui {

namespace {

unsigned long long ull(std::uint64_t v) {
    return static_cast<unsigned long long>(v);
}

// The panel's width, four lines high: ImGui 1.86's plots take a width of -1 as it is, not as "the rest of
// the line" other widgets do, and draw nothing.
ImVec2 histogramSize() {
    return {ImGui::GetContentRegionAvail().x, ImGui::GetTextLineHeight() * 4.0f};
}

void durationLine(const char* what, const engine::DurationFigures& d) {
    if (d.count == 0) {
        ImGui::TextDisabled("%s: no frames yet", what);
        return;
    }
    ImGui::Text("%s: median %.2f ms, p99 %.2f ms (%zu frames)", what, d.medianMs, d.p99Ms, d.count);
}

void streamSection(const char* name, const engine::StreamTimingSummary& s) {
    ImGui::PushID(name);
    ImGui::Text("%s: %llu frames, timestamps: %s%s", name, ull(s.frames), engine::toString(s.source),
                s.monotonic ? ", CLOCK_MONOTONIC" : "");
    if (s.lastDriverSequence)
        ImGui::Text("driver sequence %u", *s.lastDriverSequence);
    durationLine("interval", s.intervals);
    const engine::IntervalHistogram& h = s.histogram;
    if (!h.counts.empty()) {
        char range[64];
        std::snprintf(range, sizeof range, "%.2f .. %.2f ms", h.lowMs,
                      h.lowMs + h.binMs * static_cast<double>(h.counts.size()));
        ImGui::PlotHistogram("##intervals", h.counts.data(), static_cast<int>(h.counts.size()), 0, range,
                             0.0f, FLT_MAX, histogramSize());
    }
    ImGui::PopID();
}

void dropsSection(const engine::TimingSummary& t) {
    const engine::DropCounts& d = t.drops;
    ImGui::Text("frames: %llu delivered, %llu shown", ull(t.delivered), ull(t.shown));
    ImGui::TextUnformatted("lost before the screen:");
    ImGui::Indent();
    ImGui::Text("camera/USB (driver sequence gaps): %llu", ull(d.cameraUsb));
    ImGui::Text("replaced before processing: %llu", ull(d.replacedBeforeProcessing));
    ImGui::Text("skipped (before a seek, or delivered twice): %llu", ull(d.skipped));
    ImGui::Text("replaced before display: %llu", ull(d.replacedBeforeDisplay));
    ImGui::Unindent();
    if (t.recordsLost > 0)
        ImGui::TextColored(ImVec4(1.0f, 0.6f, 0.2f, 1.0f),
                           "%llu records were not read in time: counts are short", ull(t.recordsLost));
}

void latencySection(const engine::TimingSummary& t) {
    durationLine("arrival -> screen", t.arrivalToShown);
    if (t.sensorToShown.count > 0) {
        char what[80];
        std::snprintf(what, sizeof what, "%s -> screen", engine::toString(t.depth.source));
        durationLine(what, t.sensorToShown);
    } else {
        ImGui::TextDisabled(
            "sensor -> screen: n/a (the timestamps are not the sensor's on this machine's clock)");
    }
    ImGui::Indent();
    durationLine("arrival -> processing", t.waitBeforeProcessing);
    durationLine("processing", t.processing);
    durationLine("processed -> screen", t.processedToShown);
    ImGui::Unindent();
}

// The histogram of a source's skew, with the pairing tolerance's -/+ lines on it while it is on.
void skewHistogram(const engine::IntervalHistogram& h, float toleranceMs) {
    const double spanMs = h.binMs * static_cast<double>(h.counts.size());
    char range[64];
    std::snprintf(range, sizeof range, "%+.2f .. %+.2f ms", h.lowMs, h.lowMs + spanMs);
    ImGui::PlotHistogram("##skew", h.counts.data(), static_cast<int>(h.counts.size()), 0, range, 0.0f,
                         FLT_MAX, histogramSize());
    if (toleranceMs <= 0.0f)
        return;
    // PlotHistogram spreads its bars evenly over the frame less its padding.
    const ImVec2 pad = ImGui::GetStyle().FramePadding;
    const ImVec2 min{ImGui::GetItemRectMin().x + pad.x, ImGui::GetItemRectMin().y + pad.y};
    const ImVec2 max{ImGui::GetItemRectMax().x - pad.x, ImGui::GetItemRectMax().y - pad.y};
    for (const double at : {-static_cast<double>(toleranceMs), static_cast<double>(toleranceMs)}) {
        const float x = min.x + static_cast<float>((at - h.lowMs) / spanMs) * (max.x - min.x);
        ImGui::GetWindowDrawList()->AddLine({x, min.y}, {x, max.y}, IM_COL32(255, 160, 40, 255), 2.0f);
    }
}

void sourceSkewSection(const SourceSkew& s) {
    ImGui::PushID(s.name.c_str());
    const SkewFigures& f = s.recent;
    if (!s.note.empty()) {
        ImGui::TextDisabled("%s: %s", s.name.c_str(), s.note.c_str());
    } else if (f.count == 0) {
        ImGui::TextDisabled("%s: no frame shown together with the main source's yet", s.name.c_str());
    } else {
        if (s.nowMs)
            ImGui::Text("%s: now %+.2f ms", s.name.c_str(), *s.nowMs);
        else
            ImGui::Text("%s: now n/a", s.name.c_str());
        ImGui::Text("median %+.2f ms, min %+.2f ms, max %+.2f ms (%zu frames)", f.medianMs, f.minMs, f.maxMs,
                    f.count);
        if (f.toleranceMs > 0.0f)
            ImGui::Text("beyond the pairing tolerance of %.2f ms: %zu of %zu frames", f.toleranceMs,
                        f.beyondTolerance, f.count);
        else
            ImGui::TextDisabled("pairing tolerance off: every frame is fused");
        skewHistogram(f.histogram, f.toleranceMs);
    }
    ImGui::PopID();
}

void sourcesSection(const std::vector<SourceSkew>& sources) {
    ImGui::TextUnformatted("Sources: skew from the main source's frame (positive: later)");
    ImGui::Indent();
    for (const SourceSkew& s : sources)
        sourceSkewSection(s);
    ImGui::Unindent();
}

} // namespace

void drawTimingPanel(const engine::TimingSummary& timing, bool* open,
                     const std::vector<SourceSkew>& sources) {
    if (!ImGui::Begin(kTimingTitle, open)) {
        ImGui::End();
        return;
    }
    dropsSection(timing);
    ImGui::Separator();
    latencySection(timing);
    ImGui::Separator();
    streamSection("depth", timing.depth);
    if (timing.colour) {
        ImGui::Separator();
        streamSection("colour", *timing.colour);
        if (timing.colourSkew)
            durationLine("depth <-> colour skew", *timing.colourSkew);
    }
    if (!sources.empty()) {
        ImGui::Separator();
        sourcesSection(sources);
    }
    ImGui::End();
}

} // namespace dc::ui
