#include "ui/probe.h"

#include "processing/point_cloud.h"
#include "processing/registration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dc::ui {

std::optional<Probe> probeAt(const ProbeSource& source, int u, int v) {
    if (source.empty())
        return std::nullopt;
    const frame::DepthData& depth = *source.depth;
    if (u < 0 || v < 0 || u >= depth.depthMeters.width || v >= depth.depthMeters.height)
        return std::nullopt;
    Probe probe;
    probe.u = u;
    probe.v = v;
    probe.depthMeters = depth.depthMeters.at(u, v);
    if (!std::isfinite(probe.depthMeters) || probe.depthMeters < 0.0f)
        probe.depthMeters = 0.0f;
    if (!depth.confidence.empty())
        probe.confidence = static_cast<frame::Confidence>(std::min<int>(depth.confidence.at(u, v), 2));
    const frame::Plane<std::uint8_t>* seen = source.colourSeen;
    if (seen && seen->width == depth.depthMeters.width && seen->height == depth.depthMeters.height)
        probe.seenByColour = probe.depthMeters <= 0.0f || seen->at(u, v) != 0;
    else if (source.frame && probe.depthMeters > 0.0f)
        probe.seenByColour =
            processing::sampleSeenByColour(*source.frame, depth.depthMeters, source.intrinsics, u, v);
    if (const frame::Plane<std::uint16_t>* ir = source.infrared; ir && !ir->empty())
        probe.infrared =
            ir->at(u * ir->width / depth.depthMeters.width, v * ir->height / depth.depthMeters.height);
    if (source.frame) {
        probe.frameSequence = source.frame->sequence;
        probe.driverSequence = source.frame->timing.depth.driverSequence;
        probe.exposureUs = source.frame->timing.depth.exposureUs;
        const frame::CameraMetadata& camera = source.frame->timing.depthMetadata;
        probe.cameraFrameCounter = camera.frameCounter;
        probe.gain = camera.gain;
        probe.laserPowerMw = camera.laserPowerMw;
    }
    if (probe.depthMeters > 0.0f && source.intrinsics.valid())
        probe.point = processing::unproject(u, v, probe.depthMeters, source.intrinsics);
    return probe;
}

std::optional<Probe> probeAtFraction(const ProbeSource& source, ImVec2 fraction) {
    if (source.empty() ||
        !(fraction.x >= 0.0f && fraction.x < 1.0f && fraction.y >= 0.0f && fraction.y < 1.0f))
        return std::nullopt;
    const auto& d = source.depth->depthMeters;
    return probeAt(source, std::min(static_cast<int>(fraction.x * static_cast<float>(d.width)), d.width - 1),
                   std::min(static_cast<int>(fraction.y * static_cast<float>(d.height)), d.height - 1));
}

std::string formatDepth(float meters) {
    char text[32];
    if (!(meters > 0.0f))
        return "no depth";
    if (meters < 1.0f)
        std::snprintf(text, sizeof text, "%.0f mm", meters * 1000.0f);
    else
        std::snprintf(text, sizeof text, "%.3f m", meters);
    return text;
}

const char* confidenceName(frame::Confidence level) {
    switch (level) {
    case frame::Confidence::Low:
        return "low";
    case frame::Confidence::Medium:
        return "medium";
    case frame::Confidence::High:
        return "high";
    }
    return "low";
}

std::string frameReadout(const Probe& p) {
    if (!p.frameSequence)
        return {};
    std::string text = "frame " + std::to_string(*p.frameSequence);
    if (p.driverSequence)
        text += ", seq " + std::to_string(*p.driverSequence);
    if (p.exposureUs)
        text += ", exposure " + std::to_string(*p.exposureUs) + " \u00b5s";
    return text;
}

std::string cameraReadout(const Probe& p) {
    std::string text;
    const auto part = [&text](const char* name, const std::optional<std::uint32_t>& value, const char* unit) {
        if (value)
            text += (text.empty() ? "" : ", ") + std::string(name) + std::to_string(*value) + unit;
    };
    part("camera frame ", p.cameraFrameCounter, "");
    part("gain ", p.gain, "");
    part("laser ", p.laserPowerMw, " mW");
    return text;
}

void showProbeTooltip(const Probe& p) {
    ImGui::BeginTooltip();
    ImGui::Text("pixel %d, %d", p.u, p.v);
    if (const std::string frame = frameReadout(p); !frame.empty())
        ImGui::TextUnformatted(frame.c_str());
    if (const std::string camera = cameraReadout(p); !camera.empty())
        ImGui::TextUnformatted(camera.c_str());
    ImGui::Text("depth %s", formatDepth(p.depthMeters).c_str());
    ImGui::Text("confidence %s", p.confidence ? confidenceName(*p.confidence) : "none (source has none)");
    if (p.depthMeters > 0.0f)
        ImGui::Text("point %.3f, %.3f, %.3f m", p.point[0], p.point[1], p.point[2]);
    if (!p.seenByColour)
        ImGui::TextUnformatted(kNotSeenByColour);
    if (p.infrared)
        ImGui::Text("infrared %u (raw)", static_cast<unsigned>(*p.infrared));
    ImGui::EndTooltip();
}

} // namespace dc::ui
