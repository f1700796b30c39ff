#include "base/log.h"

#include <cstdio>
#include <mutex>

namespace dc {

namespace {
std::mutex gMutex;
std::function<void(LogLevel, const std::string&)> gSink;
std::uint64_t gSinkToken = 0;
bool gQuiet = false;
} // namespace

const char* toString(LogLevel level) {
    switch (level) {
    case LogLevel::Debug:
        return "debug";
    case LogLevel::Info:
        return "info";
    case LogLevel::Warning:
        return "warning";
    case LogLevel::Error:
        return "error";
    }
    return "?";
}

void log(LogLevel level, const std::string& message) {
    std::lock_guard lock(gMutex);
    const bool toStderr = level >= LogLevel::Warning || (level == LogLevel::Info && !gQuiet);
    if (toStderr)
        std::fprintf(stderr, "depthcloud: %s: %s\n", toString(level), message.c_str());
    if (gSink)
        gSink(level, message);
}

std::uint64_t setLogSink(std::function<void(LogLevel, const std::string&)> sink) {
    std::lock_guard lock(gMutex);
    gSink = std::move(sink);
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
