#include "engine/replay_follow.h"

namespace dc::engine {

std::int64_t onCompanionClock(const RecordingSpan& main, std::int64_t mainTimestampNs,
                              const RecordingSpan& companion) {
    const bool sharedClock = main.firstTimestampNs <= companion.lastTimestampNs &&
                             companion.firstTimestampNs <= main.lastTimestampNs;
    if (sharedClock)
        return mainTimestampNs;
    return companion.firstTimestampNs + (mainTimestampNs - main.firstTimestampNs);
}

std::int64_t onCompanionClock(const devices::replay::ReplayStatus& main, std::int64_t mainTimestampNs,
                              const devices::replay::ReplayStatus& companion) {
    return onCompanionClock(RecordingSpan{main.firstTimestampNs, main.lastTimestampNs}, mainTimestampNs,
                            RecordingSpan{companion.firstTimestampNs, companion.lastTimestampNs});
}

void ReplayFollower::follow(const devices::replay::ReplayStatus& main, Instrument& companion) {
    const auto& replay = companion.replay();
    if (!replay)
        return;
    const devices::replay::ReplayStatus own = replay->status();
    if (own.speed != main.speed)
        replay->setSpeed(main.speed);
    if (own.loop != main.loop)
        replay->setLoop(main.loop);
    if (followed_ != main.seekGeneration) {
        followed_ = main.seekGeneration;
        companion.seekReplayNear(onCompanionClock(main, main.timestampNs, own));
    }
    // A shorter companion rests on its last frame while the main replay plays on: play() would restart it.
    if (main.playing && !own.playing && !own.atEnd)
        replay->play();
    else if (!main.playing && own.playing)
        replay->pause();
}

} // namespace dc::engine
