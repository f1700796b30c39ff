#include "ui/settings.h"

#include "ui/settings_fields.h"

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

// A lasso's vertices as pairs: a vertex with a non-finite coordinate (or an odd coordinate left over)
// dropped, the rest clamped to [0, maxPixels], at most kMaxPolygonVertices, and none at all if fewer than 3
// remain.
void sanitizePolygon(std::vector<float>& polygon, float maxPixels) {
    std::vector<float> kept;
    for (std::size_t i = 0; i + 1 < polygon.size() && kept.size() < 2 * kMaxPolygonVertices; i += 2) {
        if (!std::isfinite(polygon[i]) || !std::isfinite(polygon[i + 1]))
            continue;
        kept.push_back(std::clamp(polygon[i], 0.0f, maxPixels));
        kept.push_back(std::clamp(polygon[i + 1], 0.0f, maxPixels));
    }
    if (kept.size() < 6)
        kept.clear();
    polygon = std::move(kept);
}

} // namespace

// A preset outside the list, a rectangle off the map or a range upside down: each put back, so that the
// engine is never asked an impossible question (the rectangle is fitted to each map there as well).
void sanitize(QualitySettings& q) {
    const QualitySettings d;
    if (q.roiPercent != 0 && std::find(std::begin(kQualityRoiPresets), std::end(kQualityRoiPresets),
                                       q.roiPercent) == std::end(kQualityRoiPresets))
        q.roiPercent = d.roiPercent;
    constexpr int kMaxPixels = 16384;
    q.roiX = std::clamp(q.roiX, 0, kMaxPixels);
    q.roiY = std::clamp(q.roiY, 0, kMaxPixels);
    q.roiWidth = std::clamp(q.roiWidth, 0, kMaxPixels);
    q.roiHeight = std::clamp(q.roiHeight, 0, kMaxPixels);
    sanitizePolygon(q.polygon, static_cast<float>(kMaxPixels));
    q.windowFrames = std::clamp(q.windowFrames, 2, 600);
    q.groundTruthMm = std::clamp(finiteOr(q.groundTruthMm, 0.0f), 0.0f, 100000.0f);
    q.baselineMm = std::clamp(finiteOr(q.baselineMm, 0.0f), 0.0f, 10000.0f);
    q.designSubpixelRms = std::clamp(finiteOr(q.designSubpixelRms, d.designSubpixelRms), 0.001f, 10.0f);
    q.nearMeters = std::clamp(finiteOr(q.nearMeters, d.nearMeters), 0.0f, 99.0f);
    q.farMeters = std::clamp(finiteOr(q.farMeters, d.farMeters), q.nearMeters + 0.01f, 100.0f);
    q.flyingThresholdMm = std::clamp(finiteOr(q.flyingThresholdMm, d.flyingThresholdMm), 1.0f, 10000.0f);
    q.map = std::clamp(q.map, 0, static_cast<int>(std::size(processing::kQualityMaps)) - 1);
}

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
    sanitize(s.quality);
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
    s.sources.pairingToleranceMs =
        std::clamp(finiteOr(s.sources.pairingToleranceMs, d.sources.pairingToleranceMs), 0.0f, 1000.0f);
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
    json j = json::object();
    for (const SettingField& f : settingFields())
        (f.section.empty() ? j : j[f.section])[f.key] = f.write(s);
    return j.dump(2) + "\n";
}

Expected<Settings> settingsFromJson(const std::string& text) {
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        return Error{"settings are not a JSON object"};
    Settings s;
    const json none = json::object();
    for (const SettingField& f : settingFields()) {
        const auto section = f.section.empty() ? j.end() : j.find(f.section);
        const json& holder = f.section.empty() ? j : section == j.end() ? none : *section;
        if (!holder.is_object())
            continue;
        if (const auto value = holder.find(f.key); value != holder.end())
            f.read(*value, s);
    }
    sanitize(s);
    return s;
}

namespace {

// Whether a field read back gives the value it was given: an enumerator out of range is not kept, a float
// field rounds what it is given.
bool sameValue(const json& given, const json& kept) {
    if (given.is_number() && kept.is_number()) {
        const double a = given.get<double>(), b = kept.get<double>();
        return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(a));
    }
    if (given.is_array() && kept.is_array() && given.size() == kept.size()) {
        for (std::size_t i = 0; i < given.size(); ++i)
            if (!sameValue(given[i], kept[i]))
                return false;
        return true;
    }
    return given == kept;
}

// What a refused value's message offers instead: a choice's names, or an example of the field's type.
std::string acceptedValues(const SettingField& field) {
    if (field.names.empty())
        return "a value like " + field.example.dump();
    std::string list = "one of: ";
    for (std::size_t i = 0; i < field.names.size(); ++i)
        list += (i ? ", " : "") + field.names[i];
    return list;
}

} // namespace

Status applySetting(Settings& settings, const std::string& assignment) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0)
        return Error{"'" + assignment + "': expected SECTION.KEY=VALUE (e.g. cloud.fillGaps=false)"};
    const std::string name = assignment.substr(0, equals), text = assignment.substr(equals + 1);
    const auto field =
        std::find_if(settingFields().begin(), settingFields().end(), [&](const SettingField& f) {
            return (f.section.empty() ? f.key : f.section + "." + f.key) == name;
        });
    if (field == settingFields().end())
        return Error{"'" + name +
                     "' is not a setting (the names are those of the settings file, SECTION.KEY)"};
    json value = json::parse(text, nullptr, false);
    if (const auto index = choiceIndex(*field, text))
        value = *index; // compared with the index the field stores
    else if (value.is_discarded())
        value = text;
    Settings changed = settings;
    field->read(value, changed);
    sanitize(changed); // a value outside the field's range comes back changed
    if (!sameValue(value, field->write(changed)))
        return Error{"'" + name + "' cannot be " + text + " (" + acceptedValues(*field) + ")"};
    settings = std::move(changed);
    return {};
}

std::string configDirectory() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
        return std::string(xdg) + "/depthcloud";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::string(home) + "/.config/depthcloud";
    return ".";
}

} // namespace dc::ui
