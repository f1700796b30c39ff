#pragma once

#include "base/rolling_stats.h"

#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace dc::engine {

// One stage as the stats panel and the status line show it.
struct StageSummary {
    std::string name;
    double medianMs = 0.0;
    double maxMs = 0.0;
    std::vector<double> history; // the last samples, oldest first
};

// The time each stage takes, from every thread that runs one (the frame processor, the GL thread).
// Thread-safe. A stage that has not run within the recent window is left out of recent(): the stats say
// what runs now, not what ran once.
class StageStats {
public:
    using Clock = std::chrono::steady_clock;
    static constexpr std::chrono::milliseconds kRecentWindow{1000};

    void add(std::string_view stage, double milliseconds, Clock::time_point now = Clock::now());
    // Stages that ran within kRecentWindow of `now`, largest median first.
    std::vector<StageSummary> recent(Clock::time_point now = Clock::now()) const;
    // Every stage that ever ran (summary.json), by name.
    std::vector<StageSummary> all() const;
    void clear();

private:
    struct Entry {
        base::RollingStats samples;
        Clock::time_point lastRun;
    };
    static StageSummary summarise(const std::string& name, const Entry& entry);

    mutable std::mutex mutex_;
    std::map<std::string, Entry, std::less<>> stages_;
};

} // namespace dc::engine
