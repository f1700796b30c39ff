#include "ui/settings_fields.h"

#include <algorithm>
#include <cctype>
#include <type_traits>

namespace dc::ui {

namespace {

using nlohmann::json;

// What an enumerator out of range becomes: an ordinal (a confidence level) takes the nearest valid one,
// a category keeps the field's value.
enum class OutOfRange { Keep, Clamp };

std::optional<int> indexOfName(const std::vector<std::string>& names, std::string_view text) {
    const auto sameIgnoringCase = [](char a, char b) {
        return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
    };
    for (std::size_t i = 0; i < names.size(); ++i)
        if (std::ranges::equal(names[i], text, sameIgnoringCase))
            return static_cast<int>(i);
    return std::nullopt;
}

// The index a choice's JSON value stores, given by name or by index; none keeps the field's value. A value
// of the wrong type throws as json's get does.
std::optional<int> choiceValue(const json& j, const std::vector<std::string>& names, OutOfRange outOfRange) {
    if (j.is_string())
        return indexOfName(names, j.get_ref<const std::string&>());
    const int count = static_cast<int>(names.size());
    int v = j.get<int>();
    if (outOfRange == OutOfRange::Clamp)
        v = std::clamp(v, 0, count - 1);
    if (v < 0 || v >= count)
        return std::nullopt;
    return v;
}

// The entry of the member `access` reaches (a lambda taking a Settings, const or not, and returning a
// reference to the member). A choice (an enumeration, or an index into a list) has `names` and is stored
// as its integer; it reads a name as well. An enumeration without names reads nothing.
template <class Access>
SettingField field(const char* section, const char* key, Access access, json example,
                   std::vector<std::string> names = {}, OutOfRange outOfRange = OutOfRange::Keep) {
    using T = std::remove_cvref_t<decltype(access(std::declval<Settings&>()))>;
    SettingField f{section, key, nullptr, nullptr, std::move(example), std::move(names)};
    f.write = [access](const Settings& s) -> json {
        if constexpr (std::is_enum_v<T>)
            return static_cast<int>(access(s));
        else
            return access(s);
    };
    f.read = [access, names = f.names, outOfRange](const json& j, Settings& s) {
        try {
            if constexpr (std::is_enum_v<T> || std::is_same_v<T, int>) {
                if (!names.empty()) {
                    if (const auto v = choiceValue(j, names, outOfRange))
                        access(s) = static_cast<T>(*v);
                    return;
                }
            }
            if constexpr (!std::is_enum_v<T>)
                access(s) = j.get<T>();
        } catch (const json::exception&) {
            // A mistyped value keeps its default: the rest of the file is still worth restoring.
        }
    };
    return f;
}

#define DC_FIELD(member)                                                                                     \
    [](auto& s) -> auto& {                                                                                   \
        return s.member;                                                                                     \
    }

// The depth panel's colormaps by the names render gives them, in the enumeration's order.
std::vector<std::string> colormapNames() {
    std::vector<std::string> names;
    for (int c = 0; c < render::kColormapCount; ++c)
        names.emplace_back(render::toString(static_cast<render::Colormap>(c)));
    return names;
}

std::vector<SettingField> panelFields() {
    return {
        field("panels", "cloud", DC_FIELD(panels.cloud), false),
        field("panels", "depth", DC_FIELD(panels.depth), false),
        field("panels", "confidence", DC_FIELD(panels.confidence), false),
        field("panels", "camera", DC_FIELD(panels.camera), false),
        field("panels", "controls", DC_FIELD(panels.controls), false),
        field("panels", "stats", DC_FIELD(panels.stats), true),
        field("panels", "log", DC_FIELD(panels.log), true),
        field("panels", "infrared", DC_FIELD(panels.infrared), true),
        field("panels", "source", DC_FIELD(panels.source), true),
        field("panels", "timeline", DC_FIELD(panels.timeline), false),
        field("panels", "fog", DC_FIELD(panels.fog), true),
        field("panels", "aura", DC_FIELD(panels.aura), true),
        field("panels", "quality", DC_FIELD(panels.quality), true),
        field("panels", "cameraControls", DC_FIELD(panels.cameraControls), true),
        field("panels", "timing", DC_FIELD(panels.timing), true),
        field("panels", "sources", DC_FIELD(panels.sources), true),
        field("window", "x", DC_FIELD(window.x), 40),
        field("window", "y", DC_FIELD(window.y), 30),
        field("window", "width", DC_FIELD(window.width), 1111),
        field("window", "height", DC_FIELD(window.height), 666),
        field("window", "maximized", DC_FIELD(window.maximized), true),
    };
}

std::vector<SettingField> cloudFields() {
    return {
        field("cloud", "minConfidence", DC_FIELD(cloud.minConfidence), 2, {"low", "medium", "high"},
              OutOfRange::Clamp),
        field("cloud", "pointSizePixels", DC_FIELD(cloud.pointSizePixels), 4.5),
        field("cloud", "fillGaps", DC_FIELD(cloud.fillGaps), false),
        field("cloud", "nearMeters", DC_FIELD(cloud.nearMeters), 0.25),
        field("cloud", "coloring", DC_FIELD(cloud.coloring), 2, {"camera", "depth", "confidence"}),
        field("cloud", "path", DC_FIELD(cloud.path), 2, {"automatic", "points", "splat"}),
        field("cloud", "decimation", DC_FIELD(cloud.decimation), 3),
        field("cloud", "autoRotate", DC_FIELD(cloud.motion.enabled), false),
        field("cloud", "rotationSpeed", DC_FIELD(cloud.motion.speed), 2.0),
        field("cloud", "scaleMovement", DC_FIELD(cloud.motion.scaleMovement), 0.25),
        field("cloud", "yawRadians", DC_FIELD(cloud.orbit.yawRadians), 0.75),
        field("cloud", "pitchRadians", DC_FIELD(cloud.orbit.pitchRadians), -0.25),
        field("cloud", "zoom", DC_FIELD(cloud.orbit.zoom), 1.75),
        field("cloud", "panX", DC_FIELD(cloud.orbit.panMeters.x), 0.125),
        field("cloud", "panY", DC_FIELD(cloud.orbit.panMeters.y), -0.0625),
        field("depthRange", "minMeters", DC_FIELD(depthRange.minMeters), 0.5),
        field("depthRange", "maxMeters", DC_FIELD(depthRange.maxMeters), 4.0),
        field("depthRange", "automatic", DC_FIELD(depthRange.automatic), false),
        field("depthRange", "colormap", DC_FIELD(depthRange.colormap), 1, colormapNames()),
        field("camera", "fill", DC_FIELD(camera.fill), true),
        field("camera", "depthOverlay", DC_FIELD(camera.depthOverlay), true),
        field("camera", "overlayOpacity", DC_FIELD(camera.overlayOpacity), 0.25),
        field("depthPanel", "colourOverlay", DC_FIELD(depthView.colourOverlay), true),
        field("depthPanel", "overlayOpacity", DC_FIELD(depthView.overlayOpacity), 0.75),
        field("accumulate", "enabled", DC_FIELD(accumulate.enabled), true),
        field("accumulate", "budgetThousands", DC_FIELD(accumulate.budgetThousands), 2000),
        field("accumulate", "voxelMillimeters", DC_FIELD(accumulate.voxelMillimeters), 2.5),
        field("sources", "pairingToleranceMs", DC_FIELD(sources.pairingToleranceMs), 20.0),
        field("record", "directory", DC_FIELD(record.directory), "/tmp/takes"),
        field("record", "jpegColor", DC_FIELD(record.jpegColor), false),
        field("record", "jpegQuality", DC_FIELD(record.jpegQuality), 75),
        field("quality", "roiPercent", DC_FIELD(quality.roiPercent), 60),
        field("quality", "roiX", DC_FIELD(quality.roiX), 12),
        field("quality", "roiY", DC_FIELD(quality.roiY), 8),
        field("quality", "roiWidth", DC_FIELD(quality.roiWidth), 64),
        field("quality", "roiHeight", DC_FIELD(quality.roiHeight), 48),
        field("quality", "polygon", DC_FIELD(quality.polygon),
              json::array({10.5, 4.0, 60.0, 8.25, 20.0, 40.0})),
        field("quality", "windowFrames", DC_FIELD(quality.windowFrames), 60),
        field("quality", "groundTruthMm", DC_FIELD(quality.groundTruthMm), 1000.0),
        field("quality", "baselineMm", DC_FIELD(quality.baselineMm), 50.0),
        field("quality", "designSubpixelRms", DC_FIELD(quality.designSubpixelRms), 0.125),
        field("quality", "nearMeters", DC_FIELD(quality.nearMeters), 0.25),
        field("quality", "farMeters", DC_FIELD(quality.farMeters), 4.5),
        field("quality", "flyingThresholdMm", DC_FIELD(quality.flyingThresholdMm), 25.0),
        field("quality", "causeOverlay", DC_FIELD(quality.causeOverlay), false),
        field("quality", "map", DC_FIELD(quality.map), 2,
              {"none", "planeResidual", "temporalStd", "fillOverWindow"}),
        field("quality", "alignment", DC_FIELD(quality.alignment), true),
        field("", "recentSources", DC_FIELD(recentSources),
              json::array({"replay:/data/a.dcrec", "synthetic"})),
    };
}

std::vector<SettingField> processingFields() {
    return {
        field("processing", "smoothing", DC_FIELD(processing.smoothing), true),
        field("processing", "upsampling", DC_FIELD(processing.upsampling), true),
        field("processing", "depthSource", DC_FIELD(processing.depthSource), 0, {"raw", "smoothed"}),
        field("processing", "alpha", DC_FIELD(processing.smoothingParams.alpha), 0.75),
        field("processing", "jumpMeters", DC_FIELD(processing.smoothingParams.jumpMeters), 0.25),
        field("processing", "holeFrames", DC_FIELD(processing.smoothingParams.holeFrames), 7),
        field("processing", "method", DC_FIELD(processing.upsamplingParams.method), 3,
              {"full", "fast", "global", "quality"}),
        field("processing", "subsample", DC_FIELD(processing.upsamplingParams.subsample), 8),
        field("processing", "outputSize", DC_FIELD(processing.upsamplingParams.size), 1,
              {"halfCamera", "fullCamera"}),
        field("processing", "radiusPixels", DC_FIELD(processing.upsamplingParams.radiusPixels), 12),
        field("processing", "epsilon", DC_FIELD(processing.upsamplingParams.epsilon), 0.0625),
        field("processing", "fitWeighted", DC_FIELD(processing.upsamplingParams.fitWeighted), false),
        field("processing", "depthNoiseMeters", DC_FIELD(processing.upsamplingParams.depthNoiseMeters),
              0.125),
        field("processing", "smoothness", DC_FIELD(processing.upsamplingParams.smoothness), 4.0),
        field("processing", "fogMaxMeters", DC_FIELD(processing.fog.fogMaxMeters), 6.5),
        field("processing", "fogBlurSigmaPixels", DC_FIELD(processing.fog.blurSigmaPixels), 9.5),
        field("processing", "fogColor", DC_FIELD(processing.fog.color), json::array({0.25, 0.5, 0.75})),
        field("processing", "fogConfidenceOverlay", DC_FIELD(processing.fog.confidenceOverlay), true),
        field("processing", "auraMatte", DC_FIELD(processing.aura.matte), 1, {"nearestRegion", "nearRange"}),
        field("processing", "auraNearMeters", DC_FIELD(processing.aura.nearMeters), 0.5),
        field("processing", "auraFarMeters", DC_FIELD(processing.aura.farMeters), 5.5),
        field("processing", "auraRegionDepthMeters", DC_FIELD(processing.aura.regionDepthMeters), 0.375),
        field("processing", "auraSeparationMeters", DC_FIELD(processing.aura.separationMeters), 0.125),
        field("processing", "auraRingPixels", DC_FIELD(processing.aura.ringPixels), 9),
    };
}

#undef DC_FIELD

} // namespace

std::optional<int> choiceIndex(const SettingField& field, std::string_view text) {
    return indexOfName(field.names, text);
}

const std::vector<SettingField>& settingFields() {
    static const std::vector<SettingField> fields = [] {
        std::vector<SettingField> all = panelFields();
        for (auto part : {cloudFields(), processingFields()})
            all.insert(all.end(), part.begin(), part.end());
        return all;
    }();
    return fields;
}

} // namespace dc::ui
