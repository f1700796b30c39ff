#pragma once

#include "base/log.h"

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dc::ui {

struct LogEntry {
    std::uint64_t id = 0; // increasing, so a toast can tell new errors from ones already shown
    std::chrono::steady_clock::time_point time;
    LogLevel level = LogLevel::Info;
    std::string message;
};

// The last messages of the process-wide log, for the log panel and the error toasts. While attached it
// is the log's sink; messages arrive from any thread (capture threads, file readers), so it only copies
// them under its own lock and the UI thread takes a snapshot once per frame.
class LogStore {
public:
    static constexpr std::size_t kCapacity = 2000;

    LogStore();
    ~LogStore();
    LogStore(const LogStore&) = delete;
    LogStore& operator=(const LogStore&) = delete;

    std::vector<LogEntry> snapshot() const;
    void add(LogLevel level, const std::string& message);

private:
    struct Shared {
        void push(LogLevel level, const std::string& message);

        mutable std::mutex mutex;
        std::deque<LogEntry> entries;
        std::uint64_t nextId = 1;
    };
    std::shared_ptr<Shared> shared_; // the sink holds it too, so a late message never dangles
    std::uint64_t sinkToken_ = 0;
};

} // namespace dc::ui
