#include "engine/stage_stats.h"

#include <algorithm>

namespace dc::engine {

void StageStats::add(std::string_view stage, double milliseconds, Clock::time_point now) {
    std::lock_guard lock(mutex_);
    auto it = stages_.find(stage);
    if (it == stages_.end())
        it = stages_.emplace(std::string(stage), Entry{base::RollingStats(), now}).first;
    it->second.samples.add(milliseconds);
    it->second.lastRun = now;
}

StageSummary StageStats::summarise(const std::string& name, const Entry& entry) {
    return {name, entry.samples.median(), entry.samples.max(), entry.samples.inOrder()};
}

std::vector<StageSummary> StageStats::recent(Clock::time_point now) const {
    std::vector<StageSummary> out;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [name, entry] : stages_)
            if (now - entry.lastRun <= kRecentWindow)
                out.push_back(summarise(name, entry));
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const StageSummary& a, const StageSummary& b) { return a.medianMs > b.medianMs; });
    return out;
}

std::vector<StageSummary> StageStats::all() const {
    std::lock_guard lock(mutex_);
    std::vector<StageSummary> out;
    for (const auto& [name, entry] : stages_)
        out.push_back(summarise(name, entry));
    return out;
}

void StageStats::clear() {
    std::lock_guard lock(mutex_);
    stages_.clear();
}

} // namespace dc::engine
