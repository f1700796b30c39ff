#include "base/log.h"

#include <cstdio>
#include <deque>
#include <mutex>
#include <utility>

namespace dc {

namespace {
std::mutex gMutex;
std::function<void(LogLevel, const std::string&)> gSink;
std::uint64_t gSinkToken = 0;
bool gQuiet = false;
// Messages logged while no sink is installed (start-up: the settings file, the source, the renderer), for
// the next sink; the oldest go first when there are too many.
constexpr std::size_t kBacklogCapacity = 200;
std::deque<std::pair<LogLevel, std::string>> gBacklog;
} // namespace

const char* toString(LogLevel level) {
    switch (level) {
    case LogLevel::Debug:
        return "debug";
    case LogLevel::Info:
        return "info";
    case LogLevel::Notice:
        return "notice";
    case LogLevel::Warning:
        return "warning";
    case LogLevel::Error:
        return "error";
    }
    return "?";
}

void log(LogLevel level, const std::string& message) {
    std::lock_guard lock(gMutex);
    const bool toStderr = level >= LogLevel::Warning || (level >= LogLevel::Info && !gQuiet);
    if (toStderr)
        std::fprintf(stderr, "depthcloud: %s: %s\n", toString(level), message.c_str());
    if (gSink) {
        gSink(level, message);
        return;
    }
    gBacklog.emplace_back(level, message);
    if (gBacklog.size() > kBacklogCapacity)
        gBacklog.pop_front();
}

std::uint64_t setLogSink(std::function<void(LogLevel, const std::string&)> sink) {
    std::lock_guard lock(gMutex);
    gSink = std::move(sink);
    if (gSink) {
        for (const auto& [level, message] : gBacklog)
            gSink(level, message);
    }
    gBacklog.clear();
    return ++gSinkToken;
}

void removeLogSink(std::uint64_t token) {
    std::lock_guard lock(gMutex);
    if (token == gSinkToken)
        gSink = nullptr;
}

void setLogQuiet(bool quiet) {
    std::lock_guard lock(gMutex);
    gQuiet = quiet;
}

} // namespace dc
