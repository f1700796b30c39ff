#include "ui/settings.h"
#include "ui/settings_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace dc::ui {
namespace {

TEST(Settings, RoundTripKeepsEveryChangedValue) {
    Settings s;
    s.panels.depth = false;
    s.panels.controls = false;
    s.cloud.minConfidence = frame::Confidence::High;
    s.cloud.pointSizePixels = 4.5f;
    s.cloud.fillGaps = false;
    s.cloud.nearMeters = 0.3f;
    s.cloud.motion.enabled = false;
    s.cloud.motion.speed = 2.0f;
    s.cloud.motion.scaleMovement = 0.25f;
    s.cloud.orbit.yawRadians = 0.7f;
    s.cloud.orbit.pitchRadians = -0.2f;
    s.cloud.orbit.zoom = 1.8f;
    s.cloud.orbit.panMeters = {0.1f, -0.05f};
    s.depthRange = {0.5f, 4.0f, true, render::Colormap::Turbo};
    s.camera = {true, true, 0.3f};
    s.depthView = {true, 0.7f};
    s.panels.stats = true;
    s.panels.log = true;
    s.processing.smoothing = true;
    s.processing.fog.blurSigmaPixels = 9.5f;
    s.processing.aura.separationMeters = 0.12f;
    rememberSource(s, "synthetic:640x480@30");
    rememberSource(s, "replay:/data/a.dcrec");

    const auto back = settingsFromJson(settingsToJson(s));
    ASSERT_TRUE(back.ok()) << back.error().message;
    const Settings& r = *back;
    EXPECT_FALSE(r.panels.depth);
    EXPECT_FALSE(r.panels.controls);
    EXPECT_TRUE(r.panels.cloud);
    EXPECT_EQ(r.cloud.minConfidence, frame::Confidence::High);
    EXPECT_FLOAT_EQ(r.cloud.pointSizePixels, 4.5f);
    EXPECT_FALSE(r.cloud.fillGaps);
    EXPECT_FLOAT_EQ(r.cloud.nearMeters, 0.3f);
    EXPECT_FALSE(r.cloud.motion.enabled);
    EXPECT_FLOAT_EQ(r.cloud.motion.speed, 2.0f);
    EXPECT_FLOAT_EQ(r.cloud.motion.scaleMovement, 0.25f);
    EXPECT_FLOAT_EQ(r.cloud.orbit.yawRadians, 0.7f);
    EXPECT_FLOAT_EQ(r.cloud.orbit.pitchRadians, -0.2f);
    EXPECT_FLOAT_EQ(r.cloud.orbit.zoom, 1.8f);
    EXPECT_FLOAT_EQ(r.cloud.orbit.panMeters.y, -0.05f);
    EXPECT_FLOAT_EQ(r.depthRange.minMeters, 0.5f);
    EXPECT_FLOAT_EQ(r.depthRange.maxMeters, 4.0f);
    EXPECT_TRUE(r.depthRange.automatic);
    EXPECT_EQ(r.depthRange.colormap, render::Colormap::Turbo);
    EXPECT_TRUE(r.camera.fill);
    EXPECT_TRUE(r.camera.depthOverlay);
    EXPECT_FLOAT_EQ(r.camera.overlayOpacity, 0.3f);
    EXPECT_TRUE(r.depthView.colourOverlay);
    EXPECT_FLOAT_EQ(r.depthView.overlayOpacity, 0.7f);
    EXPECT_TRUE(r.panels.stats);
    EXPECT_TRUE(r.panels.log);
    EXPECT_TRUE(r.processing.smoothing);
    EXPECT_FLOAT_EQ(r.processing.fog.blurSigmaPixels, 9.5f);
    EXPECT_FLOAT_EQ(r.processing.aura.separationMeters, 0.12f);
    EXPECT_EQ(r.recentSources, (std::vector<std::string>{"replay:/data/a.dcrec", "synthetic:640x480@30"}));
}

// Each saved field, set alone to its example (a valid value other than its default), comes back from the
// file as it went in, and is the only one that differs from the defaults: every field added to the table
// is covered, and no entry reads or writes another's member. The base is the defaults with a window once
// saved (a window never saved, width 0, is forgotten whole).
TEST(Settings, EveryFieldOfTheTableRoundTripsAlone) {
    Settings base;
    base.window = {0, 0, 800, 600, false};
    const std::string defaults = settingsToJson(base);
    ASSERT_GT(settingFields().size(), 60u);
    for (const SettingField& f : settingFields()) {
        SCOPED_TRACE(f.section + "." + f.key);
        Settings s = base;
        ASSERT_NE(f.write(s), f.example) << "the example is the default";
        f.read(f.example, s);
        ASSERT_EQ(f.write(s), f.example) << "the example is not a value the field holds";
        const auto back = settingsFromJson(settingsToJson(s));
        ASSERT_TRUE(back.ok());
        EXPECT_EQ(f.write(*back), f.example);
        for (const SettingField& other : settingFields()) {
            if (&other != &f) {
                EXPECT_EQ(other.write(*back), other.write(base)) << other.section << "." << other.key;
            }
        }
    }
    const nlohmann::json written = nlohmann::json::parse(defaults);
    std::size_t leaves = 0;
    for (const auto& [key, value] : written.items())
        leaves += value.is_object() ? value.size() : 1;
    EXPECT_EQ(leaves, settingFields().size()) << "the file holds exactly the table's fields";
}

TEST(Settings, RecentSourcesAreNewestFirstWithoutDuplicatesAndBounded) {
    Settings s;
    for (int i = 0; i < 12; ++i)
        rememberSource(s, "synthetic:" + std::to_string(100 + i) + "x100");
    rememberSource(s, "synthetic:105x100");
    ASSERT_EQ(s.recentSources.size(), kMaxRecentSources);
    EXPECT_EQ(s.recentSources.front(), "synthetic:105x100");
    EXPECT_EQ(s.recentSources[1], "synthetic:111x100");
    EXPECT_EQ(std::count(s.recentSources.begin(), s.recentSources.end(), "synthetic:105x100"), 1);
}

TEST(Settings, NotJsonIsAnError) {
    EXPECT_FALSE(settingsFromJson("{ not json").ok());
    EXPECT_FALSE(settingsFromJson("[1, 2]").ok());
    EXPECT_FALSE(settingsFromJson("").ok());
}

TEST(Settings, MistypedAndOutOfRangeValuesFallBackOrClamp) {
    const auto r = settingsFromJson(R"({"cloud": {"minConfidence": 9, "pointSizePixels": "big", "zoom": -3,
                                        "nearMeters": 1e30}, "depthRange": {"minMeters": 5, "maxMeters": 1},
                                        "panels": 7, "unknown": true})");
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->cloud.minConfidence, frame::Confidence::High) << "9 clamps to the highest level";
    EXPECT_FLOAT_EQ(r->cloud.pointSizePixels, Settings{}.cloud.pointSizePixels)
        << "mistyped keeps the default";
    EXPECT_GT(r->cloud.orbit.zoom, 0.0f);
    EXPECT_LE(r->cloud.nearMeters, 10.0f);
    EXPECT_LT(r->depthRange.minMeters, r->depthRange.maxMeters) << "an inverted range is repaired";
    EXPECT_TRUE(r->panels.cloud);
}

TEST(Settings, ASetNamesAFieldOfTheFileAndTakesAValueOfItsType) {
    Settings s;
    ASSERT_TRUE(applySetting(s, "cloud.fillGaps=false"));
    EXPECT_FALSE(s.cloud.fillGaps);
    ASSERT_TRUE(applySetting(s, "cloud.pointSizePixels=4.5"));
    EXPECT_FLOAT_EQ(s.cloud.pointSizePixels, 4.5f);
    ASSERT_TRUE(applySetting(s, "depthRange.colormap=1"));
    EXPECT_EQ(static_cast<int>(s.depthRange.colormap), 1);
    ASSERT_TRUE(applySetting(s, "record.directory=/tmp/takes here"));
    EXPECT_EQ(s.record.directory, "/tmp/takes here");
    ASSERT_TRUE(applySetting(s, "processing.fogColor=[0.25,0.5,0.75]"));
    EXPECT_FLOAT_EQ(s.processing.fog.color[2], 0.75f);
    ASSERT_TRUE(applySetting(s, "recentSources=[\"synthetic\"]"));
    EXPECT_EQ(s.recentSources, std::vector<std::string>{"synthetic"});
}

TEST(Settings, ABadSetNamesItsProblemAndChangesNothing) {
    Settings s;
    s.cloud.fillGaps = true;
    const Settings before = s;
    for (const char* bad : {"cloud.fillGaps=3", "cloud.fillGaps=maybe", "cloud.path=9", "cloud.path=-1",
                            "cloud.pointSizePixels=1000", "cloud.nosuch=1", "fillGaps=false",
                            "cloud.fillGaps", "=1", "processing.fogColor=[1,2]"}) {
        const Status status = applySetting(s, bad);
        EXPECT_FALSE(status) << bad;
        EXPECT_EQ(settingsToJson(s), settingsToJson(before)) << bad;
    }
    EXPECT_NE(applySetting(s, "cloud.path=9").error().message.find("'cloud.path' cannot be 9"),
              std::string::npos);
    EXPECT_NE(applySetting(s, "cloud.nosuch=1").error().message.find("'cloud.nosuch' is not a setting"),
              std::string::npos);
}

// Every choice by each of its names: `--set cloud.path=points` sets exactly the enumerator the name says.
struct NamedChoice {
    const char* assignment;
    std::function<bool(const Settings&)> holds;
};

std::vector<NamedChoice> namedChoices() {
    using frame::Confidence;
    using processing::AuraMatte;
    using processing::DepthSource;
    using processing::QualityMap;
    using processing::UpsamplingMethod;
    using processing::UpsamplingSize;
    using render::Colormap;
    using render::PointColoring;
    const auto path = [](CloudPathChoice c) { return [c](const Settings& s) { return s.cloud.path == c; }; };
    const auto coloring = [](PointColoring c) {
        return [c](const Settings& s) { return s.cloud.coloring == c; };
    };
    const auto level = [](Confidence c) {
        return [c](const Settings& s) { return s.cloud.minConfidence == c; };
    };
    const auto colormap = [](Colormap c) {
        return [c](const Settings& s) { return s.depthRange.colormap == c; };
    };
    const auto source = [](DepthSource d) {
        return [d](const Settings& s) { return s.processing.depthSource == d; };
    };
    const auto method = [](UpsamplingMethod m) {
        return [m](const Settings& s) { return s.processing.upsamplingParams.method == m; };
    };
    const auto size = [](UpsamplingSize z) {
        return [z](const Settings& s) { return s.processing.upsamplingParams.size == z; };
    };
    const auto matte = [](AuraMatte m) {
        return [m](const Settings& s) { return s.processing.aura.matte == m; };
    };
    const auto map = [](QualityMap m) {
        return [m](const Settings& s) { return processing::kQualityMaps[s.quality.map] == m; };
    };
    return {
        {"cloud.path=automatic", path(CloudPathChoice::Automatic)},
        {"cloud.path=points", path(CloudPathChoice::Points)},
        {"cloud.path=splat", path(CloudPathChoice::Splat)},
        {"cloud.coloring=camera", coloring(PointColoring::Camera)},
        {"cloud.coloring=depth", coloring(PointColoring::Depth)},
        {"cloud.coloring=confidence", coloring(PointColoring::Confidence)},
        {"cloud.minConfidence=low", level(Confidence::Low)},
        {"cloud.minConfidence=medium", level(Confidence::Medium)},
        {"cloud.minConfidence=high", level(Confidence::High)},
        {"depthRange.colormap=jet", colormap(Colormap::Jet)},
        {"depthRange.colormap=turbo", colormap(Colormap::Turbo)},
        {"depthRange.colormap=viridis", colormap(Colormap::Viridis)},
        {"depthRange.colormap=grayscale", colormap(Colormap::Grayscale)},
        {"processing.depthSource=raw", source(DepthSource::Raw)},
        {"processing.depthSource=smoothed", source(DepthSource::Smoothed)},
        {"processing.method=full", method(UpsamplingMethod::Full)},
        {"processing.method=fast", method(UpsamplingMethod::Fast)},
        {"processing.method=global", method(UpsamplingMethod::Global)},
        {"processing.method=quality", method(UpsamplingMethod::Quality)},
        {"processing.outputSize=halfCamera", size(UpsamplingSize::HalfCamera)},
        {"processing.outputSize=fullCamera", size(UpsamplingSize::FullCamera)},
        {"processing.auraMatte=nearestRegion", matte(AuraMatte::NearestRegion)},
        {"processing.auraMatte=nearRange", matte(AuraMatte::NearRange)},
        {"quality.map=none", map(QualityMap::None)},
        {"quality.map=planeResidual", map(QualityMap::PlaneResidual)},
        {"quality.map=temporalStd", map(QualityMap::TemporalStd)},
        {"quality.map=fillOverWindow", map(QualityMap::FillOverWindow)},
    };
}

std::string nameOf(const SettingField& f) {
    return f.section.empty() ? f.key : f.section + "." + f.key;
}

std::string upper(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
    return text;
}

// The table above names every choice of the file, and each choice's names are exactly the ones it lists, in
// the enumeration's order. (An enumeration given no names reads nothing: EveryFieldOfTheTableRoundTripsAlone
// fails then.)
TEST(Settings, EveryChoiceHasANameForEachOfItsValues) {
    std::map<std::string, std::vector<std::string>> listed;
    for (const NamedChoice& c : namedChoices()) {
        const std::string a = c.assignment;
        listed[a.substr(0, a.find('='))].push_back(a.substr(a.find('=') + 1));
    }
    std::map<std::string, std::vector<std::string>> named;
    for (const SettingField& f : settingFields())
        if (!f.names.empty())
            named[nameOf(f)] = f.names;
    EXPECT_EQ(named, listed);
    EXPECT_EQ(named["cloud.coloring"].size(), static_cast<std::size_t>(render::kPointColoringCount));
    EXPECT_EQ(named["depthRange.colormap"].size(), static_cast<std::size_t>(render::kColormapCount));
    EXPECT_EQ(named["quality.map"].size(), std::size(processing::kQualityMaps));
}

TEST(Settings, AChoiceTakesEachOfItsNamesInAnyCaseAndItsIndexAndSavesTheIndex) {
    for (const NamedChoice& c : namedChoices()) {
        SCOPED_TRACE(c.assignment);
        const std::string a = c.assignment, name = a.substr(0, a.find('=')), word = a.substr(a.find('=') + 1);
        const auto f = std::find_if(settingFields().begin(), settingFields().end(),
                                    [&](const SettingField& g) { return nameOf(g) == name; });
        ASSERT_NE(f, settingFields().end());
        const int index =
            static_cast<int>(std::find(f->names.begin(), f->names.end(), word) - f->names.begin());
        for (const std::string& given : {word, upper(word), std::to_string(index)}) {
            // From a value other than the named one, so that a set that changes nothing cannot pass.
            Settings s;
            ASSERT_TRUE(applySetting(s, name + "=" + f->names[(index + 1) % f->names.size()]));
            ASSERT_FALSE(c.holds(s));
            const Status set = applySetting(s, name + "=" + given);
            ASSERT_TRUE(set) << given << ": " << set.error().message;
            EXPECT_TRUE(c.holds(s)) << given;
            const std::string file = settingsToJson(s);
            EXPECT_EQ(nlohmann::json::parse(file)[f->section][f->key], index) << "the file keeps the index";
            const auto back = settingsFromJson(file);
            ASSERT_TRUE(back.ok());
            EXPECT_TRUE(c.holds(*back)) << given;
        }
        const auto byName = settingsFromJson(nlohmann::json{{f->section, {{f->key, upper(word)}}}}.dump());
        ASSERT_TRUE(byName.ok());
        EXPECT_TRUE(c.holds(*byName)) << "a file may name the value too";
    }
}

TEST(Settings, AWrongNameIsRefusedWithTheNamesItCouldBe) {
    Settings s;
    const std::string before = settingsToJson(s);
    const Status pointz = applySetting(s, "cloud.path=pointz");
    ASSERT_FALSE(pointz);
    EXPECT_EQ(pointz.error().message, "'cloud.path' cannot be pointz (one of: automatic, points, splat)");
    for (const SettingField& f : settingFields()) {
        if (f.names.empty())
            continue;
        SCOPED_TRACE(nameOf(f));
        for (const std::string wrong : {"nosuch", "9", "-1"}) {
            const Status status = applySetting(s, nameOf(f) + "=" + wrong);
            ASSERT_FALSE(status) << wrong;
            for (const std::string& name : f.names)
                EXPECT_NE(status.error().message.find(name), std::string::npos) << wrong;
        }
    }
    EXPECT_EQ(settingsToJson(s), before);
}

TEST(Settings, SanitizeRemovesNonFiniteValues) {
    Settings s;
    s.cloud.orbit.yawRadians = std::nanf("");
    s.cloud.pointSizePixels = INFINITY;
    s.depthRange.maxMeters = -INFINITY;
    s.processing.fog.blurSigmaPixels = -3.0f;
    s.processing.aura.separationMeters = std::nanf("");
    s.depthView.overlayOpacity = std::nanf("");
    sanitize(s);
    EXPECT_EQ(s.depthView.overlayOpacity, DepthView{}.overlayOpacity);
    EXPECT_EQ(s.processing.fog.blurSigmaPixels, 0.0f);
    EXPECT_EQ(s.processing.aura.separationMeters, processing::AuraSettings{}.separationMeters);
    EXPECT_TRUE(std::isfinite(s.cloud.orbit.yawRadians));
    EXPECT_TRUE(std::isfinite(s.cloud.pointSizePixels));
    EXPECT_GT(s.depthRange.maxMeters, s.depthRange.minMeters);
}

// The Quality panel's section: every field survives the file, `--set quality.KEY=VALUE` reaches it, and a
// preset that is not one of DQT's, a window too short to measure noise or a range upside down is refused.
TEST(Settings, TheQualitySectionRoundTripsAndTakesSets) {
    Settings s;
    s.panels.quality = true;
    s.quality = {0,    10,    20,    30,     40,    45, 1234.5f, 0.3f,
                 3.5f, 20.0f, 50.0f, 0.125f, false, 2,  true,    {1.5f, 2.0f, 30.0f, 2.0f, 1.5f, 20.25f}};
    const auto back = settingsFromJson(settingsToJson(s));
    ASSERT_TRUE(back.ok());
    const QualitySettings& q = back->quality;
    EXPECT_TRUE(back->panels.quality);
    EXPECT_EQ(q.roiPercent, 0);
    EXPECT_EQ(q.roiX, 10);
    EXPECT_EQ(q.roiY, 20);
    EXPECT_EQ(q.roiWidth, 30);
    EXPECT_EQ(q.roiHeight, 40);
    EXPECT_EQ(q.windowFrames, 45);
    EXPECT_FLOAT_EQ(q.groundTruthMm, 1234.5f);
    EXPECT_FLOAT_EQ(q.nearMeters, 0.3f);
    EXPECT_FLOAT_EQ(q.farMeters, 3.5f);
    EXPECT_FLOAT_EQ(q.flyingThresholdMm, 20.0f);
    EXPECT_FLOAT_EQ(q.baselineMm, 50.0f);
    EXPECT_FLOAT_EQ(q.designSubpixelRms, 0.125f);
    EXPECT_EQ(q.polygon, s.quality.polygon);
    // A lasso read back: a vertex with a non-finite coordinate and an odd coordinate left over dropped, and
    // fewer than 3 vertices none at all.
    QualitySettings lasso;
    lasso.polygon = {1.0f, 2.0f, std::nanf(""), 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f};
    sanitize(lasso);
    EXPECT_EQ(lasso.polygon, (std::vector<float>{1.0f, 2.0f, 4.0f, 5.0f, 6.0f, 7.0f}));
    lasso.polygon = {1.0f, 2.0f, 4.0f, 5.0f, std::numeric_limits<float>::infinity(), 7.0f};
    sanitize(lasso);
    EXPECT_TRUE(lasso.polygon.empty());
    lasso.polygon.assign(2 * (kMaxPolygonVertices + 10), 1.0f);
    sanitize(lasso);
    EXPECT_EQ(lasso.polygon.size(), 2 * kMaxPolygonVertices);

    Settings t;
    ASSERT_TRUE(applySetting(t, "quality.roiPercent=80"));
    EXPECT_EQ(t.quality.roiPercent, 80);
    ASSERT_TRUE(applySetting(t, "quality.windowFrames=60"));
    EXPECT_EQ(t.quality.windowFrames, 60);
    ASSERT_TRUE(applySetting(t, "quality.groundTruthMm=1000"));
    EXPECT_FLOAT_EQ(t.quality.groundTruthMm, 1000.0f);
    ASSERT_TRUE(applySetting(t, "panels.quality=true"));
    EXPECT_TRUE(t.panels.quality);
    for (const char* bad :
         {"quality.roiPercent=33", "quality.windowFrames=1", "quality.farMeters=-1", "quality.nosuch=1"})
        EXPECT_FALSE(applySetting(t, bad)) << bad;
    EXPECT_EQ(t.quality.roiPercent, 80);
}

} // namespace
} // namespace dc::ui
