#include "ui/settings.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace dc::ui {

namespace {

using nlohmann::json;

float finiteOr(float v, float fallback) {
    return std::isfinite(v) ? v : fallback;
}

template <class T> void read(const json& j, const char* key, T& out) {
    const auto it = j.find(key);
    if (it == j.end())
        return;
    try {
        out = it->get<T>();
    } catch (const json::exception&) {
        // A mistyped value keeps its default: the rest of the file is still worth restoring.
    }
}

} // namespace

void sanitize(CloudSettings& c) {
    const Settings d;
    c.pointSizePixels = std::clamp(finiteOr(c.pointSizePixels, d.cloud.pointSizePixels), 1.0f, 16.0f);
    c.nearMeters = std::clamp(finiteOr(c.nearMeters, d.cloud.nearMeters), 0.0f, 10.0f);
    c.motion.speed = std::clamp(finiteOr(c.motion.speed, d.cloud.motion.speed), 0.0f, 10.0f);
    c.motion.scaleMovement =
        std::clamp(finiteOr(c.motion.scaleMovement, d.cloud.motion.scaleMovement), 0.0f, 2.0f);
    c.orbit.yawRadians = std::remainder(finiteOr(c.orbit.yawRadians, 0.0f), 2.0f * static_cast<float>(M_PI));
    c.orbit.pitchRadians = std::clamp(finiteOr(c.orbit.pitchRadians, 0.0f), -1.5f, 1.5f);
    c.orbit.zoom = std::clamp(finiteOr(c.orbit.zoom, 1.0f), 0.1f, 20.0f);
    c.orbit.panMeters.x = std::clamp(finiteOr(c.orbit.panMeters.x, 0.0f), -50.0f, 50.0f);
    c.orbit.panMeters.y = std::clamp(finiteOr(c.orbit.panMeters.y, 0.0f), -50.0f, 50.0f);
    const auto level = static_cast<int>(c.minConfidence);
    if (level < 0 || level > 2)
        c.minConfidence = d.cloud.minConfidence;
}

void sanitize(Settings& s) {
    const Settings d;
    sanitize(s.cloud);
    auto& r = s.depthRange;
    r.minMeters = std::clamp(finiteOr(r.minMeters, d.depthRange.minMeters), 0.0f, 99.0f);
    r.maxMeters = std::clamp(finiteOr(r.maxMeters, d.depthRange.maxMeters), r.minMeters + 0.01f, 100.0f);
    const auto colormap = static_cast<int>(r.colormap);
    if (colormap < 0 || colormap >= render::kColormapCount)
        r.colormap = d.depthRange.colormap;
    s.camera.overlayOpacity =
        std::clamp(finiteOr(s.camera.overlayOpacity, d.camera.overlayOpacity), 0.0f, 1.0f);
    s.accumulate.budgetThousands = std::clamp(s.accumulate.budgetThousands, 10, 4000);
    s.accumulate.voxelMillimeters =
        std::clamp(finiteOr(s.accumulate.voxelMillimeters, d.accumulate.voxelMillimeters), 0.5f, 100.0f);
    if (s.recentSources.size() > kMaxRecentSources)
        s.recentSources.resize(kMaxRecentSources);
}

void rememberSource(Settings& settings, const std::string& source) {
    auto& recent = settings.recentSources;
    recent.erase(std::remove(recent.begin(), recent.end(), source), recent.end());
    recent.insert(recent.begin(), source);
    if (recent.size() > kMaxRecentSources)
        recent.resize(kMaxRecentSources);
}

std::string settingsToJson(const Settings& s) {
    const auto& c = s.cloud;
    json j;
    j["panels"] = {
        {"cloud", s.panels.cloud},   {"depth", s.panels.depth},       {"confidence", s.panels.confidence},
        {"camera", s.panels.camera}, {"controls", s.panels.controls}, {"stats", s.panels.stats},
        {"log", s.panels.log}};
    j["cloud"] = {{"minConfidence", static_cast<int>(c.minConfidence)},
                  {"pointSizePixels", c.pointSizePixels},
                  {"nearMeters", c.nearMeters},
                  {"autoRotate", c.motion.enabled},
                  {"rotationSpeed", c.motion.speed},
                  {"scaleMovement", c.motion.scaleMovement},
                  {"yawRadians", c.orbit.yawRadians},
                  {"pitchRadians", c.orbit.pitchRadians},
                  {"zoom", c.orbit.zoom},
                  {"panX", c.orbit.panMeters.x},
                  {"panY", c.orbit.panMeters.y}};
    j["depthRange"] = {{"minMeters", s.depthRange.minMeters},
                       {"maxMeters", s.depthRange.maxMeters},
                       {"automatic", s.depthRange.automatic},
                       {"colormap", static_cast<int>(s.depthRange.colormap)}};
    j["camera"] = {{"fill", s.camera.fill},
                   {"depthOverlay", s.camera.depthOverlay},
                   {"overlayOpacity", s.camera.overlayOpacity}};
    j["accumulate"] = {{"enabled", s.accumulate.enabled},
                       {"budgetThousands", s.accumulate.budgetThousands},
                       {"voxelMillimeters", s.accumulate.voxelMillimeters}};
    j["recentSources"] = s.recentSources;
    j["processing"] = {{"smoothing", s.processing.smoothing}, {"upsampling", s.processing.upsampling}};
    return j.dump(2) + "\n";
}

Expected<Settings> settingsFromJson(const std::string& text) {
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        return Error{"settings are not a JSON object"};
    Settings s;
    const json none = json::object();
    const json& p = j.contains("panels") ? j["panels"] : none;
    read(p, "cloud", s.panels.cloud);
    read(p, "depth", s.panels.depth);
    read(p, "confidence", s.panels.confidence);
    read(p, "camera", s.panels.camera);
    read(p, "controls", s.panels.controls);
    read(p, "stats", s.panels.stats);
    read(p, "log", s.panels.log);
    read(p, "source", s.panels.source);
    read(p, "timeline", s.panels.timeline);
    const json& c = j.contains("cloud") ? j["cloud"] : none;
    int level = static_cast<int>(s.cloud.minConfidence);
    read(c, "minConfidence", level);
    s.cloud.minConfidence = static_cast<devices::Confidence>(std::clamp(level, 0, 2));
    read(c, "pointSizePixels", s.cloud.pointSizePixels);
    read(c, "nearMeters", s.cloud.nearMeters);
    read(c, "autoRotate", s.cloud.motion.enabled);
    read(c, "rotationSpeed", s.cloud.motion.speed);
    read(c, "scaleMovement", s.cloud.motion.scaleMovement);
    read(c, "yawRadians", s.cloud.orbit.yawRadians);
    read(c, "pitchRadians", s.cloud.orbit.pitchRadians);
    read(c, "zoom", s.cloud.orbit.zoom);
    read(c, "panX", s.cloud.orbit.panMeters.x);
    read(c, "panY", s.cloud.orbit.panMeters.y);
    const json& r = j.contains("depthRange") ? j["depthRange"] : none;
    read(r, "minMeters", s.depthRange.minMeters);
    read(r, "maxMeters", s.depthRange.maxMeters);
    read(r, "automatic", s.depthRange.automatic);
    int colormap = static_cast<int>(s.depthRange.colormap);
    read(r, "colormap", colormap);
    s.depthRange.colormap = static_cast<render::Colormap>(colormap);
    const json& cam = j.contains("camera") ? j["camera"] : none;
    read(cam, "fill", s.camera.fill);
    read(cam, "depthOverlay", s.camera.depthOverlay);
    read(cam, "overlayOpacity", s.camera.overlayOpacity);
    const json& acc = j.contains("accumulate") ? j["accumulate"] : none;
    read(acc, "enabled", s.accumulate.enabled);
    read(acc, "budgetThousands", s.accumulate.budgetThousands);
    read(acc, "voxelMillimeters", s.accumulate.voxelMillimeters);
    read(j, "recentSources", s.recentSources);
    const json& pr = j.contains("processing") ? j["processing"] : none;
    read(pr, "smoothing", s.processing.smoothing);
    read(pr, "upsampling", s.processing.upsampling);
    sanitize(s);
    return s;
}

std::string configDirectory() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
        return std::string(xdg) + "/depthcloud";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::string(home) + "/.config/depthcloud";
    return ".";
}

} // namespace dc::ui
