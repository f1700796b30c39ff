#include "tool/summary.h"

#include <nlohmann/json.hpp>

namespace dc::tool {

std::string summaryJson(const ui::ViewerSummary& s, const std::string& renderer, const std::string& mode) {
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
    return j.dump(2) + "\n";
}

} // namespace dc::tool
