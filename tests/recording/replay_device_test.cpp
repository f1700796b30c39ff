// The replay device: exact seeks and steps, pacing order, loop and end, bad chunks skipped.

#include "base/log.h"
#include "devices/recording/recording_reader.h"
#include "devices/replay/importers.h"
#include "devices/replay/replay_device.h"
#include "devices/session.h"
#include "tests/recording/recording_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>
#include <random>
#include <string>
#include <vector>

namespace dc::devices::replay {
namespace {

using test::TempDir;
constexpr auto kWait = std::chrono::seconds(5);

class Replay : public ::testing::Test {
protected:
    void SetUp() override {
        frames_ = test::syntheticFrames(kFrames);
        test::writeRecording(dir_.path("r.dcrec"), frames_);
    }
    std::unique_ptr<ReplayDevice> device(ReplayOptions options = {}) {
        auto source = openRecordingSource(dir_.path("r.dcrec"));
        EXPECT_TRUE(source);
        return std::make_unique<ReplayDevice>(std::move(*source), options);
    }
    // Captures until a frame of generation >= `generation` arrives, as a consumer after a seek does.
    static frame::FramePtr frameOfGeneration(Device& d, std::uint64_t generation) {
        const auto deadline = std::chrono::steady_clock::now() + kWait;
        while (std::chrono::steady_clock::now() < deadline) {
            auto r = d.capture(std::chrono::milliseconds(50));
            if (r.kind == CaptureResult::Kind::Frame && r.frame->replay->seekGeneration >= generation)
                return r.frame;
        }
        return nullptr;
    }
    void expectFrame(const frame::FramePtr& f, std::size_t index) {
        ASSERT_TRUE(f);
        ASSERT_TRUE(f->replay);
        EXPECT_EQ(f->replay->index, index);
        EXPECT_EQ(f->replay->count, kFrames);
        EXPECT_EQ(f->timestampNs, frames_[index]->timestampNs);
        EXPECT_TRUE(test::sameBits(f->sceneDepth->depthMeters, frames_[index]->sceneDepth->depthMeters));
    }

    static constexpr std::size_t kFrames = 24;
    TempDir dir_;
    std::vector<frame::FramePtr> frames_;
};

TEST_F(Replay, SeekToEveryIndexDeliversExactlyThatFrame) {
    auto d = device({.startPlaying = false});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    auto control = d->control();
    expectFrame(frameOfGeneration(*d, 0), 0);
    for (std::size_t i = 0; i < kFrames; ++i)
        expectFrame(frameOfGeneration(*d, control->seekToIndex(i)), i);
    for (std::size_t i = kFrames; i-- > 0;)
        expectFrame(frameOfGeneration(*d, control->seekToIndex(i)), i);
    EXPECT_EQ(control->status().index, 0u);
}

// A replayed frame carries the timing its recording kept, for the Timing panel and the hover readout.
TEST_F(Replay, ReplayedFramesCarryTheRecordedTiming) {
    frames_ = test::withTiming(frames_);
    std::filesystem::remove(dir_.path("r.dcrec"));
    test::writeRecording(dir_.path("r.dcrec"), frames_);
    auto d = device({.startPlaying = false});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    auto control = d->control();
    for (const std::size_t i : {std::size_t{3}, std::size_t{0}, std::size_t{1}, kFrames - 1}) {
        const auto f = frameOfGeneration(*d, control->seekToIndex(i));
        expectFrame(f, i);
        SCOPED_TRACE(i);
        // As recorded, except that the stamps are no longer this machine's clock now.
        frame::FrameTiming expected = frames_[i]->timing;
        EXPECT_TRUE(expected.depth.monotonic) << "recorded as monotonic";
        expected.depth.monotonic = false;
        if (expected.colour)
            expected.colour->monotonic = false;
        test::expectSameTiming(f->timing, expected);
    }
}

TEST_F(Replay, StepsForwardAndBackwardOneFrameAtATime) {
    auto d = device();
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    auto control = d->control();
    expectFrame(frameOfGeneration(*d, 0), 0);
    for (std::size_t i = 1; i < kFrames; ++i)
        expectFrame(frameOfGeneration(*d, control->step(+1)), i);
    EXPECT_FALSE(control->status().playing) << "stepping pauses";
    expectFrame(frameOfGeneration(*d, control->step(+1)), kFrames - 1);
    for (std::size_t i = kFrames - 1; i-- > 0;)
        expectFrame(frameOfGeneration(*d, control->step(-1)), i);
    expectFrame(frameOfGeneration(*d, control->step(-1)), 0);
    expectFrame(frameOfGeneration(*d, control->step(+5)), 5);
}

TEST_F(Replay, RandomSeeksByIndexAndByTimeWhilePlayingAreExact) {
    auto d = device({.loop = true, .speed = 4.0});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    auto control = d->control();
    std::mt19937 rng(7);
    for (int n = 0; n < 60; ++n) {
        const std::size_t target = rng() % kFrames;
        if (n % 2 == 0) {
            expectFrame(frameOfGeneration(*d, control->seekToIndex(target)), target);
        } else {
            // A time inside the frame's interval shows that frame.
            const std::int64_t t = frames_[target]->timestampNs + 1'000'000;
            expectFrame(frameOfGeneration(*d, control->seekToTime(t)), target);
        }
    }
    expectFrame(frameOfGeneration(*d, control->seekToTime(0)), 0);
    expectFrame(frameOfGeneration(*d, control->seekToTime(frames_.back()->timestampNs + 10'000'000'000)),
                kFrames - 1);
}

TEST_F(Replay, LatestSeekWinsWhenRequestsPileUp) {
    auto d = device({.startPlaying = false});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    auto control = d->control();
    control->seekToIndex(3);
    control->seekToIndex(9);
    const auto g = control->seekToIndex(17);
    auto f = frameOfGeneration(*d, g);
    expectFrame(f, 17);
    EXPECT_EQ(f->replay->seekGeneration, g);
}

TEST_F(Replay, PlaybackDeliversFramesInOrderThenPausesAtTheEnd) {
    auto d = device({.speed = 4.0});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    std::size_t expected = 0;
    while (expected < kFrames) {
        auto r = d->capture(std::chrono::milliseconds(500));
        ASSERT_NE(r.kind, CaptureResult::Kind::Error) << r.message;
        if (r.kind != CaptureResult::Kind::Frame)
            continue;
        expectFrame(r.frame, expected);
        ++expected;
    }
    auto after = d->capture(std::chrono::milliseconds(200));
    EXPECT_EQ(after.kind, CaptureResult::Kind::Timeout);
    EXPECT_TRUE(d->control()->status().atEnd);
    EXPECT_FALSE(d->control()->status().playing);
    d->control()->play();
    expectFrame(frameOfGeneration(*d, 1), 0); // play at the end starts over
}

TEST_F(Replay, LoopWrapsToTheFirstFrame) {
    auto d = device({.loop = true, .speed = 4.0});
    ASSERT_TRUE(d->open());
    ASSERT_TRUE(d->start());
    frameOfGeneration(*d, d->control()->seekToIndex(kFrames - 2));
    std::vector<std::size_t> seen;
    while (seen.size() < 3) {
        auto r = d->capture(std::chrono::milliseconds(500));
        if (r.kind == CaptureResult::Kind::Frame)
            seen.push_back(r.frame->replay->index);
    }
    EXPECT_EQ(seen, (std::vector<std::size_t>{kFrames - 1, 0, 1}));
}

TEST_F(Replay, SpeedIsClampedAndCapabilitiesComeFromTheSource) {
    auto d = device();
    d->control()->setSpeed(100.0);
    EXPECT_EQ(d->control()->status().speed, ReplayControl::kMaxSpeed);
    d->control()->setSpeed(0.0);
    EXPECT_EQ(d->control()->status().speed, ReplayControl::kMinSpeed);
    EXPECT_TRUE(d->capabilities().confidence);
    EXPECT_NE(d->description().find("test camera"), std::string::npos);
}

TEST_F(Replay, BadChunkIsSkippedWithAWarningAndPlaybackContinues) {
    auto reader = recording::RecordingReader::open(dir_.path("r.dcrec"));
    ASSERT_TRUE(reader);
    auto bytes = test::readBytes(dir_.path("r.dcrec"));
    // Damage frame 5's payload: its offset is where frame 4's chunk ends, found by scanning headers.
    std::uint64_t offset = recording::kFileHeaderSize;
    for (int chunk = 0; chunk <= 6; ++chunk) { // the description chunk, then frames 0..5
        const auto h =
            recording::decodeChunkHeader(std::span(bytes).subspan(offset, recording::kChunkHeaderSize));
        ASSERT_TRUE(h);
        if (chunk == 6)
            bytes[offset + recording::kChunkHeaderSize + 10] ^= 1;
        else
            offset += recording::kChunkHeaderSize + h->payloadSize;
    }
    test::writeBytes(dir_.path("bad.dcrec"), bytes);
    auto source = openRecordingSource(dir_.path("bad.dcrec"));
    ASSERT_TRUE(source);
    ReplayDevice d(std::move(*source), {.speed = 4.0});
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    std::vector<std::size_t> seen;
    while (seen.size() < 8) {
        auto r = d.capture(std::chrono::milliseconds(500));
        if (r.kind == CaptureResult::Kind::Frame)
            seen.push_back(r.frame->replay->index);
    }
    EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1, 2, 3, 4, 6, 7, 8}));
    const ReplayStatus status = d.control()->status();
    EXPECT_EQ(status.framesSkipped, 1u);
    EXPECT_NE(status.lastProblem.find("frame 5"), std::string::npos) << status.lastProblem;
    // A seek to the bad frame delivers the next good one, and says so through its index.
    auto f = frameOfGeneration(d, d.control()->seekToIndex(5));
    ASSERT_TRUE(f);
    EXPECT_EQ(f->replay->index, 6u);
}

// A recording whose frames all went bad from some point on (its file overwritten, its folder deleted during
// the replay) says so a few times and then once in a summary, not once per frame.
TEST_F(Replay, ManyBadFramesInARowAreReportedOnceNotOncePerFrame) {
    auto bytes = test::readBytes(dir_.path("r.dcrec"));
    std::uint64_t offset = recording::kFileHeaderSize;
    for (std::size_t chunk = 0; chunk <= kFrames; ++chunk) { // the description chunk, then every frame
        const auto h =
            recording::decodeChunkHeader(std::span(bytes).subspan(offset, recording::kChunkHeaderSize));
        ASSERT_TRUE(h);
        if (chunk >= 6) // frames 5 to the last
            bytes[offset + recording::kChunkHeaderSize + 10] ^= 1;
        offset += recording::kChunkHeaderSize + h->payloadSize;
    }
    test::writeBytes(dir_.path("bad.dcrec"), bytes);
    // This replay's warnings only: a new sink also hears what was logged before it (earlier tests').
    std::vector<std::string> warnings;
    std::mutex mutex;
    const std::string file = dir_.path("bad.dcrec");
    const std::uint64_t sink = setLogSink([&](LogLevel level, const std::string& message) {
        const std::lock_guard lock(mutex);
        if (level == LogLevel::Warning && message.starts_with("replay: skip") &&
            message.find(file) != std::string::npos)
            warnings.push_back(message);
    });
    auto source = openRecordingSource(dir_.path("bad.dcrec"));
    ASSERT_TRUE(source);
    ReplayDevice d(std::move(*source), {.speed = 4.0});
    ASSERT_TRUE(d.open());
    ASSERT_TRUE(d.start());
    // The replay pauses at its end; what it skipped on the way is reported by then.
    std::size_t frames = 0;
    const auto deadline = std::chrono::steady_clock::now() + kWait;
    while (!d.control()->status().atEnd && std::chrono::steady_clock::now() < deadline)
        frames += d.capture(std::chrono::milliseconds(50)).kind == CaptureResult::Kind::Frame;
    frames += d.capture(std::chrono::milliseconds(200)).kind == CaptureResult::Kind::Frame;
    removeLogSink(sink);
    EXPECT_EQ(frames, 5u);
    EXPECT_EQ(d.control()->status().framesSkipped, kFrames - 5);
    const std::lock_guard lock(mutex);
    ASSERT_EQ(warnings.size(), 4u);
    EXPECT_NE(warnings.back().find("skipped " + std::to_string(kFrames - 5 - 3) + " more"), std::string::npos)
        << warnings.back();
    EXPECT_NE(warnings.back().find("frame " + std::to_string(kFrames - 1)), std::string::npos)
        << warnings.back();
}

TEST_F(Replay, RunsThroughASessionLikeALiveCamera) {
    Session session(device({.loop = true, .speed = 4.0}));
    ASSERT_TRUE(session.start());
    std::set<std::size_t> indices;
    for (int i = 0; i < 20; ++i) {
        auto f = session.waitForFrame(kWait);
        ASSERT_TRUE(f && *f);
        indices.insert((*f)->replay->index);
    }
    EXPECT_GT(indices.size(), 3u);
    session.stop();
}

} // namespace
} // namespace dc::devices::replay
