#include "tool/summary.h"

#include <nlohmann/json.hpp>

namespace dc::tool {

namespace {

// One further source's own figures: its frames add up on their own (shown + dropped + in flight =
// delivered), and its overlap with the first source as placed.
nlohmann::json companionJson(const ui::ViewerSummary& s) {
    const engine::FrameCounts& f = s.frames;
    nlohmann::json j{{"source", s.source},
                     {"frames", f.shown},
                     {"framesDropped", f.dropped},
                     {"framesDelivered", f.delivered},
                     {"deviceFps", f.deliveredPerSecond},
                     {"viewerFps", f.shownPerSecond},
                     {"depthWidth", s.depthWidth},
                     {"depthHeight", s.depthHeight}};
    j["latencyMs"] = s.latencyMs ? nlohmann::json(*s.latencyMs) : nlohmann::json(nullptr);
    if (s.overlap)
        j["overlap"] = {{"medianMm", s.overlap->medianMm},
                        {"overlapFraction", s.overlap->overlapFraction},
                        {"pairs", s.overlap->count}};
    else
        j["overlap"] = nullptr;
    j["skewMs"] = s.skewMs ? nlohmann::json(*s.skewMs) : nlohmann::json(nullptr);
    return j;
}

} // namespace

std::string summaryJson(const ui::ViewerSummary& s, const std::string& renderer, const std::string& mode,
                        const std::vector<ui::ViewerSummary>& companions) {
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& t : s.stages)
        stages[t.name] = t.medianMs;
    const engine::FrameCounts& f = s.frames;
    // frames + framesDropped + the few still on their way = framesDelivered; rates over the same window.
    nlohmann::json j{{"mode", mode},
                     {"source", s.source},
                     {"renderer", renderer},
                     {"frames", f.shown},
                     {"framesDropped", f.dropped},
                     {"framesDelivered", f.delivered},
                     {"deviceFps", f.deliveredPerSecond},
                     {"viewerFps", f.shownPerSecond},
                     {"uiFps", s.uiFps},
                     {"uiFramesDrawn", s.uiFramesDrawn},
                     {"uiFramesKept", s.uiFramesKept},
                     {"pointsDrawn", s.pointsDrawn},
                     {"cloudPath", s.cloudPath},
                     {"depthWidth", s.depthWidth},
                     {"depthHeight", s.depthHeight},
                     {"stageMedianMs", stages}};
    // null, not 0, for a source whose timestamps are not comparable with the clock (a recording).
    j["latencyMs"] = s.latencyMs ? nlohmann::json(*s.latencyMs) : nlohmann::json(nullptr);
    if (!companions.empty()) {
        j["companions"] = nlohmann::json::array();
        for (const ui::ViewerSummary& c : companions)
            j["companions"].push_back(companionJson(c));
    }
    return j.dump(2) + "\n";
}

} // namespace dc::tool
