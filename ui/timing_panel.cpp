// The Timing panel: where a stutter comes from. Per stream the intervals between frames (a steady camera
// is one bar, jitter widens it, a lost frame is a bar at twice the period) and what its timestamps mark;
// the latency from arrival, and from the sensor where its clock is this machine's, to the screen, with
// the parts it is made of; and every frame that did not reach the screen, counted where it was lost.

#include "ui/panels.h"

#include <imgui.h>

#include <cfloat>
#include <cstdio>

namespace dc::ui {

namespace {

unsigned long long ull(std::uint64_t v) {
    return static_cast<unsigned long long>(v);
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
                             0.0f, FLT_MAX, ImVec2(-1.0f, ImGui::GetTextLineHeight() * 4.0f));
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

} // namespace

void drawTimingPanel(const engine::TimingSummary& timing, bool* open) {
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
    ImGui::End();
}

} // namespace dc::ui
