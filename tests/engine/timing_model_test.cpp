// The Timing model: intervals, the driver's sequence, latencies and the place each lost frame was lost,
// first from hand-made records, then through a real Session, FrameProcessor and Instrument, where its
// counts must equal the engine's own counters and a count made independently from what the test fed in.

#include "engine/timing_model.h"

#include "base/clock.h"
#include "engine/instrument.h"
#include "engine_test_support.h"

#include <gtest/gtest.h>

namespace dc::engine::test {
namespace {

using namespace std::chrono_literals;
using devices::FrameRecord;

constexpr std::int64_t kMs = 1'000'000;

frame::FrameTiming driverTiming(std::uint32_t sequence, std::int64_t sensorNs,
                                frame::TimestampSource source = frame::TimestampSource::StartOfExposure) {
    frame::FrameTiming t;
    t.depth = {.driverSequence = sequence,
               .sensorNs = sensorNs,
               .source = source,
               .monotonic = true,
               .exposureUs = std::nullopt};
    return t;
}

FrameRecord delivered(std::uint64_t sequence, frame::FrameTiming timing, std::int64_t arrivalNs) {
    return {FrameRecord::Kind::Delivered, sequence, timing.depth.sensorNs, timing, arrivalNs};
}

TEST(TimingModelTest, GapsInTheDriversSequenceAreFramesLostInTheCameraAcrossWrapAndRestart) {
    TimingModel model;
    // 10 11 13 17: 1 + 3 missing. Then far ahead (a restarted stream): none. 0xFFFFFFFE -> 1 wraps over
    // 0xFFFFFFFF and 0: 2 missing. 1 -> 0 goes back (a reconnect): none.
    const std::uint32_t sequences[] = {10, 11, 13, 17, 0xFFFFFFFEu, 1, 0};
    std::uint64_t n = 0;
    for (const std::uint32_t s : sequences) {
        model.add(delivered(n, driverTiming(s, (100 + static_cast<std::int64_t>(n) * 33) * kMs), 0));
        ++n;
    }
    const TimingSummary t = model.summary();
    EXPECT_EQ(t.drops.cameraUsb, 6u);
    EXPECT_EQ(t.delivered, 7u);
    EXPECT_EQ(t.depth.frames, 7u);
    EXPECT_EQ(t.depth.lastDriverSequence, 0u);
    EXPECT_EQ(t.depth.source, frame::TimestampSource::StartOfExposure);
    EXPECT_TRUE(t.depth.monotonic);
    ASSERT_EQ(t.depth.intervals.count, 6u);
    EXPECT_DOUBLE_EQ(t.depth.intervals.medianMs, 33.0);
}

// A replay's recorded sequence jumps where the person seeks; only gaps within one seek generation are frames
// the camera lost when it was recorded.
TEST(TimingModelTest, ASeekInAReplayIsNoFrameLost) {
    TimingModel model;
    const auto replayed = [](std::uint64_t n, std::uint32_t sequence, std::uint64_t generation) {
        FrameRecord r = delivered(n, driverTiming(sequence, static_cast<std::int64_t>(n) * 33 * kMs), 0);
        r.seekGeneration = generation;
        return r;
    };
    // 1 2 4 (1 lost when recorded), a seek to 40 41, a seek back to 3, 5 (1 lost).
    model.add(replayed(0, 1, 0));
    model.add(replayed(1, 2, 0));
    model.add(replayed(2, 4, 0));
    model.add(replayed(3, 40, 1));
    model.add(replayed(4, 41, 1));
    model.add(replayed(5, 3, 2));
    model.add(replayed(6, 5, 2));
    const TimingSummary t = model.summary();
    EXPECT_EQ(t.drops.cameraUsb, 2u);
    EXPECT_EQ(t.depth.intervals.count, 4u) << "none across a seek";
}

TEST(TimingModelTest, EachLostFrameIsCountedWhereItWasLostAndShownFramesHaveTheirLatencies) {
    TimingModel model;
    // Frame 0: shown. 1: replaced in the session's slot. 2: processed, its result replaced. 3: a capture
    // delivered twice, skipped. 4: shown.
    for (std::int64_t s = 0; s < 5; ++s)
        model.add(delivered(static_cast<std::uint64_t>(s),
                            driverTiming(static_cast<std::uint32_t>(s), 1000 * kMs + 10 * kMs * s),
                            1004 * kMs + 10 * kMs * s));
    model.add(FrameRecord{FrameRecord::Kind::Replaced, 1, 0, {}, 0});
    model.add(ProcessorRecord{ProcessorRecord::Kind::Processed, 0, 1005 * kMs, 1007 * kMs});
    model.add(ProcessorRecord{ProcessorRecord::Kind::Processed, 2, 1025 * kMs, 1027 * kMs});
    model.add(ProcessorRecord{ProcessorRecord::Kind::Unshown, 2, 0, 0});
    model.add(ProcessorRecord{ProcessorRecord::Kind::Skipped, 3, 0, 0});
    model.add(ProcessorRecord{ProcessorRecord::Kind::Processed, 4, 1045 * kMs, 1049 * kMs});
    model.shown(0, 1010 * kMs);
    model.shown(4, 1054 * kMs);

    const TimingSummary t = model.summary();
    EXPECT_EQ(t.drops.cameraUsb, 0u);
    EXPECT_EQ(t.drops.replacedBeforeProcessing, 1u);
    EXPECT_EQ(t.drops.replacedBeforeDisplay, 1u);
    EXPECT_EQ(t.drops.skipped, 1u);
    EXPECT_EQ(t.drops.afterArrival(), 3u);
    EXPECT_EQ(t.shown, 2u);
    // Arrival -> screen: 6 and 10 ms; start of exposure -> screen: 10 and 14 ms.
    ASSERT_EQ(t.arrivalToShown.count, 2u);
    EXPECT_DOUBLE_EQ(t.arrivalToShown.medianMs, 8.0);
    EXPECT_DOUBLE_EQ(t.arrivalToShown.p99Ms, 10.0);
    ASSERT_EQ(t.sensorToShown.count, 2u);
    EXPECT_DOUBLE_EQ(t.sensorToShown.medianMs, 12.0);
    EXPECT_DOUBLE_EQ(t.processing.medianMs, 2.0); // 2, 2 and 4 ms
    EXPECT_DOUBLE_EQ(t.waitBeforeProcessing.p99Ms, 1.0);
    EXPECT_DOUBLE_EQ(t.processedToShown.medianMs, 4.0); // 3 and 5 ms
}

TEST(TimingModelTest, OnlyMonotonicSensorStampsGiveALatencyFromTheSensor) {
    TimingModel model;
    model.add(delivered(0, driverTiming(0, 100 * kMs, frame::TimestampSource::Arrival), 100 * kMs));
    frame::FrameTiming recorded = driverTiming(1, 110 * kMs);
    recorded.depth.monotonic = false; // a recording's clock
    model.add(delivered(1, recorded, 111 * kMs));
    model.shown(0, 120 * kMs);
    model.shown(1, 130 * kMs);
    const TimingSummary t = model.summary();
    EXPECT_EQ(t.arrivalToShown.count, 2u);
    EXPECT_EQ(t.sensorToShown.count, 0u);
}

TEST(TimingModelTest, PairedColourHasItsOwnIntervalsAndItsSkewToDepth) {
    TimingModel model;
    for (std::uint32_t s = 0; s < 4; ++s) {
        frame::FrameTiming t = driverTiming(s, (100 + 50 * static_cast<std::int64_t>(s)) * kMs);
        t.colour = frame::StreamTiming{.driverSequence = s + 7,
                                       .sensorNs = t.depth.sensorNs + 3 * kMs,
                                       .source = frame::TimestampSource::EndOfFrame,
                                       .monotonic = true,
                                       .exposureUs = std::nullopt};
        model.add(delivered(s, t, 0));
    }
    const TimingSummary t = model.summary();
    ASSERT_TRUE(t.colour);
    EXPECT_EQ(t.colour->frames, 4u);
    EXPECT_EQ(t.colour->source, frame::TimestampSource::EndOfFrame);
    EXPECT_EQ(t.colour->lastDriverSequence, 10u);
    EXPECT_DOUBLE_EQ(t.colour->intervals.medianMs, 50.0);
    ASSERT_TRUE(t.colourSkew);
    EXPECT_DOUBLE_EQ(t.colourSkew->medianMs, 3.0);
}

TEST(TimingModelTest, FiguresAreTheMedianTheNearestRankP99AndEqualBins) {
    std::vector<double> samples;
    for (int i = 1; i <= 200; ++i)
        samples.push_back(i);
    const DurationFigures f = durationFigures(samples);
    EXPECT_EQ(f.count, 200u);
    EXPECT_DOUBLE_EQ(f.medianMs, 100.5);
    EXPECT_DOUBLE_EQ(f.p99Ms, 198.0);

    const IntervalHistogram h = intervalHistogram({10.0, 10.0, 10.0, 20.0, 14.0}, 2);
    EXPECT_DOUBLE_EQ(h.lowMs, 10.0);
    EXPECT_DOUBLE_EQ(h.binMs, 5.0);
    EXPECT_EQ(h.counts, (std::vector<float>{4.0f, 1.0f}));
    const IntervalHistogram steady = intervalHistogram({33.0, 33.0}, 4);
    EXPECT_DOUBLE_EQ(steady.binMs, 1.0);
    EXPECT_EQ(steady.counts[0], 2.0f);
}

// Synthetic frames as a UVC camera would stamp them: the driver's sequence skips one after every third
// frame (frames the camera lost), the start of exposure just before delivery on CLOCK_MONOTONIC.
std::vector<frame::FramePtr> framesWithGaps(int count, std::uint64_t first) {
    std::vector<frame::FramePtr> out;
    for (const frame::FramePtr& f : syntheticFrames(count, first)) {
        auto copy = std::make_shared<frame::Frame>(*f);
        const std::uint64_t i = f->sequence;
        copy->timing = driverTiming(static_cast<std::uint32_t>(i + i / 3), base::monotonicNowNs());
        out.push_back(std::move(copy));
    }
    return out;
}

// What the test fed in says independently how many frames the camera lost: the driver counted
// last - first + 1 frames and the application got `frames.size()` of them.
std::uint64_t lostInCamera(const std::vector<frame::FramePtr>& frames) {
    return *frames.back()->timing.depth.driverSequence - *frames.front()->timing.depth.driverSequence + 1 -
           frames.size();
}

TEST(TimingInstrumentTest, DropsAttributedByTheModelEqualTheEngineCountersAndAnIndependentCount) {
    auto device = std::make_unique<ScriptedDevice>(0.0);
    ScriptedDevice& source = *device;
    Instrument instrument(std::move(device), "scripted");
    instrument.start();

    // No demand yet: the processor takes nothing, so every frame but the newest is replaced in the slot.
    constexpr int kUntaken = 12;
    const std::vector<frame::FramePtr> untaken = framesWithGaps(kUntaken, 0);
    source.push(untaken);
    ASSERT_TRUE(waitUntil([&] { return instrument.status().frames.delivered == kUntaken; }));
    instrument.setDemand(cloudAndPanels());
    auto r = instrument.waitForResult(10s, true);
    ASSERT_TRUE(r);
    instrument.presented(**r);

    // Each frame processed before the next comes, and no result taken: every result but the last is
    // replaced before display.
    constexpr int kUnshown = 5;
    const std::vector<frame::FramePtr> unshown = framesWithGaps(kUnshown, kUntaken);
    for (int i = 0; i < kUnshown; ++i) {
        source.push(unshown[static_cast<std::size_t>(i)]);
        ASSERT_TRUE(waitUntil([&] { return instrument.processor().counts().framesProcessed == 2u + i; }));
    }
    r = instrument.waitForResult(10s, true);
    ASSERT_TRUE(r);
    instrument.presented(**r);
    // The capture shown delivered again: skipped.
    source.push(std::make_shared<frame::Frame>(*unshown.back()));
    ASSERT_TRUE(waitUntil([&] { return instrument.processor().counts().framesSkipped == 1u; }));

    const TimingSummary t = instrument.timing();
    const FrameCounts counts = instrument.status().frames;
    const ProcessorCounts processor = instrument.processor().counts();
    std::vector<frame::FramePtr> all = untaken;
    all.insert(all.end(), unshown.begin(), unshown.end());
    EXPECT_EQ(t.drops.cameraUsb, lostInCamera(all));
    EXPECT_EQ(t.drops.cameraUsb, 5u); // after frames 2, 5, 8, 11 and 14
    EXPECT_EQ(t.drops.replacedBeforeProcessing, kUntaken - 1u);
    // The session's own count: FrameCounts::dropped is it plus the processor's two.
    EXPECT_EQ(t.drops.replacedBeforeProcessing,
              counts.dropped - processor.framesUnshown - processor.framesSkipped);
    EXPECT_EQ(t.drops.replacedBeforeDisplay, kUnshown - 1u);
    EXPECT_EQ(t.drops.replacedBeforeDisplay, processor.framesUnshown);
    EXPECT_EQ(t.drops.skipped, 1u);
    EXPECT_EQ(t.drops.skipped, processor.framesSkipped);
    EXPECT_EQ(t.drops.afterArrival(), counts.dropped);
    EXPECT_EQ(t.delivered, counts.delivered);
    EXPECT_EQ(t.shown, counts.shown);
    EXPECT_EQ(t.shown, 2u);
    EXPECT_EQ(t.recordsLost, 0u);
    // Both frames shown went through arrival, processing and the screen, from a sensor stamp before arrival.
    EXPECT_EQ(t.arrivalToShown.count, 2u);
    EXPECT_EQ(t.sensorToShown.count, 2u);
    EXPECT_GE(t.sensorToShown.medianMs, t.arrivalToShown.medianMs);
    EXPECT_EQ(t.processing.count, 1u + kUnshown);
    EXPECT_EQ(t.depth.source, frame::TimestampSource::StartOfExposure);
}

} // namespace
} // namespace dc::engine::test
