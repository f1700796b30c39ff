#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace dc {

// Notice: what the user asked for is done (a file saved, a take recorded); the window shows it as a toast,
// as it shows warnings and errors.
enum class LogLevel { Debug, Info, Notice, Warning, Error };

const char* toString(LogLevel level);

// Process-wide logging: every message goes to stderr (Info and above) and to an optional sink that the
// UI installs to show messages in its status line. Thread-safe; the sink is called with the lock held, so
// it must only copy the message.
void log(LogLevel level, const std::string& message);
// Installs `sink` in place of any other and returns a token for removeLogSink(), which removes it only if it
// is still the one installed: a sink's owner going away late must not remove its successor's sink. The
// sink first hears what was logged while none was installed (the last 200 messages), so the log panel
// shows the start-up messages.
std::uint64_t setLogSink(std::function<void(LogLevel, const std::string&)> sink);
void removeLogSink(std::uint64_t token);
void setLogQuiet(bool quiet); // keep stderr for warnings and errors only (headless runs, tests)

inline void logInfo(const std::string& m) {
    log(LogLevel::Info, m);
}
inline void logNotice(const std::string& m) {
    log(LogLevel::Notice, m);
}
inline void logWarning(const std::string& m) {
    log(LogLevel::Warning, m);
}
inline void logError(const std::string& m) {
    log(LogLevel::Error, m);
}

} // namespace dc
