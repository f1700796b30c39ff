#include "ui/log_store.h"

namespace dc::ui {

void LogStore::Shared::push(LogLevel level, const std::string& message) {
    std::lock_guard lock(mutex);
    entries.push_back({nextId++, std::chrono::steady_clock::now(), level, message});
    if (entries.size() > kCapacity)
        entries.pop_front();
}

LogStore::LogStore() : shared_(std::make_shared<Shared>()) {
    sinkToken_ = setLogSink(
        [shared = shared_](LogLevel level, const std::string& message) { shared->push(level, message); });
}

LogStore::~LogStore() {
    removeLogSink(sinkToken_);
}

void LogStore::add(LogLevel level, const std::string& message) {
    shared_->push(level, message);
}

std::vector<LogEntry> LogStore::snapshot() const {
    std::lock_guard lock(shared_->mutex);
    return {shared_->entries.begin(), shared_->entries.end()};
}

} // namespace dc::ui
