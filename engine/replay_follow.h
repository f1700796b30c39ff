#pragma once

#include "devices/replay/replay_device.h"
#include "engine/instrument.h"

#include <cstdint>
#include <optional>

namespace dc::engine {

// A recording's span of time: its first and last frames' timestamps.
struct RecordingSpan {
    std::int64_t firstTimestampNs = 0;
    std::int64_t lastTimestampNs = 0;
};

// Where `mainTimestampNs` of the main replay falls on a companion replay's clock: the same instant when the
// two recordings' spans overlap (they were recorded together, on one clock), else the same time since each
// one's first frame.
std::int64_t onCompanionClock(const RecordingSpan& main, std::int64_t mainTimestampNs,
                              const RecordingSpan& companion);
// The same for two replays as they play.
std::int64_t onCompanionClock(const devices::replay::ReplayStatus& main, std::int64_t mainTimestampNs,
                              const devices::replay::ReplayStatus& companion);

// Keeps a companion's replay with the main replay's timeline: the same play state, speed and loop, and after
// every seek or step of the main replay, the companion's frame nearest the main one's on the common clock.
// Between seeks each plays at its own recorded pace.
class ReplayFollower {
public:
    // Once per UI frame; nothing when the companion is no replay.
    void follow(const devices::replay::ReplayStatus& main, Instrument& companion);

private:
    std::optional<std::uint64_t> followed_; // the main replay's seek generation followed last
};

} // namespace dc::engine
