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

json processingToJson(const processing::ProcessingSettings& p) {
    const auto& sm = p.smoothingParams;
    const auto& up = p.upsamplingParams;
    return {{"smoothing", p.smoothing},
            {"upsampling", p.upsampling},
            {"depthSource", static_cast<int>(p.depthSource)},
            {"alpha", sm.alpha},
            {"jumpMeters", sm.jumpMeters},
            {"holeFrames", sm.holeFrames},
            {"method", static_cast<int>(up.method)},
            {"subsample", up.subsample},
            {"outputSize", static_cast<int>(up.size)},
            {"radiusPixels", up.radiusPixels},
            {"epsilon", up.epsilon},
            {"fitWeighted", up.fitWeighted},
            {"depthNoiseMeters", up.depthNoiseMeters},
            {"smoothness", up.smoothness},
            {"fogMaxMeters", p.fog.fogMaxMeters},
            {"fogBlurSigmaPixels", p.fog.blurSigmaPixels},
            {"fogColor", p.fog.color},
            {"fogConfidenceOverlay", p.fog.confidenceOverlay},
            {"auraMatte", static_cast<int>(p.aura.matte)},
            {"auraNearMeters", p.aura.nearMeters},
            {"auraFarMeters", p.aura.farMeters},
            {"auraRegionDepthMeters", p.aura.regionDepthMeters},
            {"auraSeparationMeters", p.aura.separationMeters},
            {"auraRingPixels", p.aura.ringPixels}};
}

template <class E> void readEnum(const json& j, const char* key, E& out, int count) {
    int v = static_cast<int>(out);
    read(j, key, v);
    if (v >= 0 && v < count)
        out = static_cast<E>(v);
}

void processingFromJson(const json& j, processing::ProcessingSettings& p) {
    auto& sm = p.smoothingParams;
    auto& up = p.upsamplingParams;
    read(j, "smoothing", p.smoothing);
    read(j, "upsampling", p.upsampling);
    readEnum(j, "depthSource", p.depthSource, 2);
    read(j, "alpha", sm.alpha);
    read(j, "jumpMeters", sm.jumpMeters);
    read(j, "holeFrames", sm.holeFrames);
    readEnum(j, "method", up.method, 4);
    read(j, "subsample", up.subsample);
    readEnum(j, "outputSize", up.size, 2);
    read(j, "radiusPixels", up.radiusPixels);
    read(j, "epsilon", up.epsilon);
    read(j, "fitWeighted", up.fitWeighted);
    read(j, "depthNoiseMeters", up.depthNoiseMeters);
    read(j, "smoothness", up.smoothness);
    read(j, "fogMaxMeters", p.fog.fogMaxMeters);
    read(j, "fogBlurSigmaPixels", p.fog.blurSigmaPixels);
    read(j, "fogColor", p.fog.color);
    read(j, "fogConfidenceOverlay", p.fog.confidenceOverlay);
    readEnum(j, "auraMatte", p.aura.matte, 2);
    read(j, "auraNearMeters", p.aura.nearMeters);
    read(j, "auraFarMeters", p.aura.farMeters);
    read(j, "auraRegionDepthMeters", p.aura.regionDepthMeters);
    read(j, "auraSeparationMeters", p.aura.separationMeters);
    read(j, "auraRingPixels", p.aura.ringPixels);
}

// Keeps the processing parameters where the stages are defined and stable.
void sanitize(processing::ProcessingSettings& p) {
    const processing::ProcessingSettings d;
    auto& sm = p.smoothingParams;
    auto& up = p.upsamplingParams;
    sm.alpha = std::clamp(finiteOr(sm.alpha, d.smoothingParams.alpha), 0.01f, 1.0f);
    sm.jumpMeters = std::clamp(finiteOr(sm.jumpMeters, d.smoothingParams.jumpMeters), 0.001f, 10.0f);
    sm.holeFrames = std::clamp(sm.holeFrames, 0, 120);
    if (up.subsample != 2 && up.subsample != 4 && up.subsample != 8)
        up.subsample = d.upsamplingParams.subsample;
    up.radiusPixels = std::clamp(up.radiusPixels, 1, 64);
    up.epsilon = std::clamp(finiteOr(up.epsilon, d.upsamplingParams.epsilon), 1e-6f, 1.0f);
    up.depthNoiseMeters =
        std::clamp(finiteOr(up.depthNoiseMeters, d.upsamplingParams.depthNoiseMeters), 1e-4f, 1.0f);
    up.smoothness = std::clamp(finiteOr(up.smoothness, d.upsamplingParams.smoothness), 0.01f, 100.0f);
    p.fog.fogMaxMeters = std::clamp(finiteOr(p.fog.fogMaxMeters, d.fog.fogMaxMeters), 0.1f, 100.0f);
    p.fog.blurSigmaPixels = std::clamp(finiteOr(p.fog.blurSigmaPixels, d.fog.blurSigmaPixels), 0.0f, 50.0f);
    for (float& c : p.fog.color)
        c = std::clamp(finiteOr(c, 0.8f), 0.0f, 1.0f);
    p.aura.nearMeters = std::clamp(finiteOr(p.aura.nearMeters, d.aura.nearMeters), 0.0f, 50.0f);
    p.aura.farMeters =
        std::clamp(finiteOr(p.aura.farMeters, d.aura.farMeters), p.aura.nearMeters + 0.01f, 100.0f);
    p.aura.regionDepthMeters =
        std::clamp(finiteOr(p.aura.regionDepthMeters, d.aura.regionDepthMeters), 0.01f, 10.0f);
    p.aura.separationMeters =
        std::clamp(finiteOr(p.aura.separationMeters, d.aura.separationMeters), 0.001f, 5.0f);
    p.aura.ringPixels = std::clamp(p.aura.ringPixels, 1, 100);
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
    const auto coloring = static_cast<int>(c.coloring);
    if (coloring < 0 || coloring >= render::kPointColoringCount)
        c.coloring = d.cloud.coloring;
    const auto path = static_cast<int>(c.path);
    if (path < 0 || path > static_cast<int>(CloudPathChoice::Splat))
        c.path = d.cloud.path;
    c.decimation = std::clamp(c.decimation, 0, kMaxDecimation);
}

void sanitize(Settings& s) {
    const Settings d;
    sanitize(s.cloud);
    auto& r = s.depthRange;
    r.minMeters = std::clamp(finiteOr(r.minMeters, d.depthRange.minMeters), 0.0f, 99.0f);
    r.maxMeters = std::clamp(finiteOr(r.maxMeters, d.depthRange.maxMeters), r.minMeters + 0.01f, 100.0f);
    sanitize(s.processing);
    const auto colormap = static_cast<int>(r.colormap);
    if (colormap < 0 || colormap >= render::kColormapCount)
        r.colormap = d.depthRange.colormap;
    s.camera.overlayOpacity =
        std::clamp(finiteOr(s.camera.overlayOpacity, d.camera.overlayOpacity), 0.0f, 1.0f);
    s.depthView.overlayOpacity =
        std::clamp(finiteOr(s.depthView.overlayOpacity, d.depthView.overlayOpacity), 0.0f, 1.0f);
    s.accumulate.budgetThousands = std::clamp(s.accumulate.budgetThousands, 10, 4000);
    s.accumulate.voxelMillimeters =
        std::clamp(finiteOr(s.accumulate.voxelMillimeters, d.accumulate.voxelMillimeters), 0.5f, 100.0f);
    s.record.jpegQuality = std::clamp(s.record.jpegQuality, 1, 100);
    if (s.record.directory.empty())
        s.record.directory = d.record.directory;
    if (s.recentSources.size() > kMaxRecentSources)
        s.recentSources.resize(kMaxRecentSources);
    constexpr int kMaxWindowPixels = 16384;
    if (s.window.width <= 0 || s.window.height <= 0 || s.window.width > kMaxWindowPixels ||
        s.window.height > kMaxWindowPixels)
        s.window = d.window;
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
        {"cloud", s.panels.cloud},       {"depth", s.panels.depth},       {"confidence", s.panels.confidence},
        {"camera", s.panels.camera},     {"controls", s.panels.controls}, {"stats", s.panels.stats},
        {"log", s.panels.log},           {"infrared", s.panels.infrared}, {"source", s.panels.source},
        {"timeline", s.panels.timeline}, {"fog", s.panels.fog},           {"aura", s.panels.aura}};
    j["window"] = {{"x", s.window.x},
                   {"y", s.window.y},
                   {"width", s.window.width},
                   {"height", s.window.height},
                   {"maximized", s.window.maximized}};
    j["cloud"] = {{"minConfidence", static_cast<int>(c.minConfidence)},
                  {"pointSizePixels", c.pointSizePixels},
                  {"fillGaps", c.fillGaps},
                  {"nearMeters", c.nearMeters},
                  {"coloring", static_cast<int>(c.coloring)},
                  {"path", static_cast<int>(c.path)},
                  {"decimation", c.decimation},
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
    j["depthPanel"] = {{"colourOverlay", s.depthView.colourOverlay},
                       {"overlayOpacity", s.depthView.overlayOpacity}};
    j["accumulate"] = {{"enabled", s.accumulate.enabled},
                       {"budgetThousands", s.accumulate.budgetThousands},
                       {"voxelMillimeters", s.accumulate.voxelMillimeters}};
    j["record"] = {{"directory", s.record.directory},
                   {"jpegColor", s.record.jpegColor},
                   {"jpegQuality", s.record.jpegQuality}};
    j["recentSources"] = s.recentSources;
    j["processing"] = processingToJson(s.processing);
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
    read(p, "fog", s.panels.fog);
    read(p, "aura", s.panels.aura);
    read(p, "infrared", s.panels.infrared);
    const json& w = j.contains("window") ? j["window"] : none;
    read(w, "x", s.window.x);
    read(w, "y", s.window.y);
    read(w, "width", s.window.width);
    read(w, "height", s.window.height);
    read(w, "maximized", s.window.maximized);
    const json& c = j.contains("cloud") ? j["cloud"] : none;
    int level = static_cast<int>(s.cloud.minConfidence);
    read(c, "minConfidence", level);
    s.cloud.minConfidence = static_cast<frame::Confidence>(std::clamp(level, 0, 2));
    read(c, "pointSizePixels", s.cloud.pointSizePixels);
    read(c, "fillGaps", s.cloud.fillGaps);
    read(c, "nearMeters", s.cloud.nearMeters);
    int coloring = static_cast<int>(s.cloud.coloring);
    read(c, "coloring", coloring);
    s.cloud.coloring = static_cast<render::PointColoring>(coloring); // sanitize() checks the range
    int path = static_cast<int>(s.cloud.path);
    read(c, "path", path);
    s.cloud.path = static_cast<CloudPathChoice>(path);
    read(c, "decimation", s.cloud.decimation);
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
    const json& dp = j.contains("depthPanel") ? j["depthPanel"] : none;
    read(dp, "colourOverlay", s.depthView.colourOverlay);
    read(dp, "overlayOpacity", s.depthView.overlayOpacity);
    const json& acc = j.contains("accumulate") ? j["accumulate"] : none;
    read(acc, "enabled", s.accumulate.enabled);
    read(acc, "budgetThousands", s.accumulate.budgetThousands);
    read(acc, "voxelMillimeters", s.accumulate.voxelMillimeters);
    const json& rec = j.contains("record") ? j["record"] : none;
    read(rec, "directory", s.record.directory);
    read(rec, "jpegColor", s.record.jpegColor);
    read(rec, "jpegQuality", s.record.jpegQuality);
    read(j, "recentSources", s.recentSources);
    processingFromJson(j.contains("processing") ? j["processing"] : none, s.processing);
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
