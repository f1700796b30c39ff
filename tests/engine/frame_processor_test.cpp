// The frame processor's hand-over: nothing before the first demand, latest wins at both ends and every
// frame is accounted for, a demand change redoes the current frame while the source is silent, and a seek
// drops what was decoded before it.

#include "base/log.h"
#include "engine/frame_processor.h"
#include "engine/instrument.h"
#include "engine_test_support.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace dc::engine::test {
namespace {

using namespace std::chrono_literals;

bool any(const processing::ShownFrame&) {
    return true;
}

// A processor fed by a scripted device through a real Session, as the Instrument wires them.
class FrameProcessorTest : public ::testing::Test {
protected:
    void start(double fps = 0.0) {
        auto device = std::make_unique<ScriptedDevice>(fps);
        device_ = device.get();
        session_ = std::make_shared<devices::Session>(std::move(device));
        ASSERT_TRUE(session_->start().ok());
        processor_.setSession(session_);
    }
    void SetUp() override { ASSERT_NO_FATAL_FAILURE(start()); }

    // Every frame the source delivered was taken by the processor (or replaced in the mailbox first).
    bool settled() const {
        const devices::SessionStats s = session_->stats();
        const ProcessorCounts c = processor_.counts();
        return s.framesDropped + c.framesProcessed + c.framesSkipped == s.framesCaptured;
    }

    StageStats stages_;
    processing::AccumulationWorker accumulation_;
    std::shared_ptr<devices::Session> session_;
    ScriptedDevice* device_ = nullptr;
    FrameProcessor processor_{stages_, accumulation_};
};

TEST_F(FrameProcessorTest, NothingIsProcessedBeforeTheFirstDemand) {
    device_->push(syntheticFrames(3));
    ASSERT_TRUE(waitUntil([&] { return session_->stats().framesCaptured == 3; }));
    EXPECT_EQ(processor_.counts().framesProcessed, 0u);
    EXPECT_EQ(processor_.stageRuns(kPointCountStage), 0u);
    EXPECT_FALSE(processor_.take());

    const std::uint64_t generation = processor_.setDemand(cloudAndPanels());
    const auto result = processor_.waitFor(10s, any);
    ASSERT_TRUE(result);
    EXPECT_EQ((*result)->frame->sequence, 2u) << "the newest frame, not the first";
    EXPECT_EQ((*result)->demandGeneration, generation);
    EXPECT_TRUE((*result)->newFrame);
    EXPECT_EQ(processor_.counts().framesProcessed, 1u);
}

TEST_F(FrameProcessorTest, ASlowConsumerGetsTheNewestFrameAndEveryOtherIsCounted) {
    processor_.setSession(nullptr);
    ASSERT_NO_FATAL_FAILURE(start(240.0));
    processor_.setDemand(cloudAndPanels());
    constexpr std::uint64_t kFrames = 30;
    device_->push(syntheticFrames(kFrames));
    std::uint64_t newTaken = 0;
    std::uint64_t lastSequence = 0;
    // A consumer drawing at ~20 fps while the source delivers at 240.
    while (session_->stats().framesCaptured < kFrames) {
        if (auto r = processor_.take()) {
            EXPECT_GE((*r)->frame->sequence, lastSequence);
            lastSequence = (*r)->frame->sequence;
            newTaken += (*r)->newFrame;
        }
        std::this_thread::sleep_for(50ms); // the slow frame itself, not a synchronisation
    }
    ASSERT_TRUE(waitUntil([&] { return settled(); }));
    const auto last = processor_.waitFor(10s, any);
    ASSERT_TRUE(last);
    EXPECT_EQ((*last)->frame->sequence, kFrames - 1);
    newTaken += (*last)->newFrame;

    const ProcessorCounts c = processor_.counts();
    EXPECT_GT(c.framesUnshown, 0u) << "the consumer was slower than the source";
    EXPECT_EQ(c.framesProcessed, c.framesUnshown + newTaken);
    EXPECT_EQ(session_->stats().framesDropped + c.framesProcessed + c.framesSkipped, kFrames);
    EXPECT_EQ(c.redone, 0u);
}

TEST_F(FrameProcessorTest, ADemandChangeRedoesTheCurrentFrameWhileTheSourceIsSilent) {
    Demand d = cloudAndPanels();
    processor_.setDemand(d);
    device_->push(syntheticFrames(2));
    ASSERT_TRUE(
        processor_.waitFor(10s, [](const processing::ShownFrame& s) { return s.frame->sequence == 1; }));

    // The source says nothing more; each change still gets its own result, on the same frame.
    d.processing.upsampling = true;
    const std::uint64_t upsampled = processor_.setDemand(d);
    EXPECT_EQ(processor_.setDemand(d), upsampled) << "the same demand again is no change";
    auto r = processor_.waitFor(
        10s, [&](const processing::ShownFrame& s) { return s.demandGeneration == upsampled; });
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->frame->sequence, 1u);
    EXPECT_FALSE((*r)->newFrame);
    EXPECT_TRUE((*r)->depth.upsampled);
    EXPECT_NE((*r)->depth.width(), 256);

    d.fog = true;
    const std::uint64_t fog = processor_.setDemand(d);
    r = processor_.waitFor(10s, [&](const processing::ShownFrame& s) { return s.demandGeneration == fog; });
    ASSERT_TRUE(r);
    EXPECT_TRUE((*r)->fog);
    EXPECT_EQ((*r)->frame->sequence, 1u);

    const ProcessorCounts c = processor_.counts();
    EXPECT_EQ(c.redone, 2u) << "one redo per change, none for the repeated demand";
    EXPECT_EQ(c.framesProcessed + c.framesSkipped + session_->stats().framesDropped, 2u);
}

// A smaller budget starts accumulation over with the newest points: the shown frame's, at once, though no
// new frame comes (a paused replay).
TEST_F(FrameProcessorTest, AccumulationFollowsABudgetChangeWhileTheSourceIsSilent) {
    Demand d = cloudAndPanels();
    d.accumulate = true;
    d.accumulateBudget = 300'000;
    processor_.setDemand(d);
    device_->push(syntheticFrames(2));
    ASSERT_TRUE(
        processor_.waitFor(10s, [](const processing::ShownFrame& s) { return s.frame->sequence == 1; }));
    accumulation_.waitIdle();
    const std::size_t oneFrame = accumulation_.size();
    ASSERT_GT(oneFrame, 2'000u);

    d.accumulateBudget = 2'000;
    const std::uint64_t smaller = processor_.setDemand(d);
    const auto r = processor_.waitFor(
        10s, [&](const processing::ShownFrame& s) { return s.demandGeneration == smaller; });
    ASSERT_TRUE(r);
    EXPECT_FALSE((*r)->newFrame) << "the same frame, redone";
    accumulation_.waitIdle();
    EXPECT_EQ(accumulation_.size(), 2'000u);
}

TEST_F(FrameProcessorTest, AfterASeekFramesDecodedBeforeItAreDroppedAndSmoothingStartsOver) {
    Demand d = cloudAndPanels();
    d.processing.smoothing = true;
    const std::vector<frame::FramePtr> frames = syntheticFrames(3);
    processor_.setDemand(d);
    device_->push(asReplayed(frames[0], 0));
    ASSERT_TRUE(processor_.waitFor(10s, any));
    device_->push(asReplayed(frames[1], 0));
    auto r = processor_.waitFor(10s, [](const processing::ShownFrame& s) { return s.frame->sequence == 1; });
    ASSERT_TRUE(r);
    ASSERT_TRUE((*r)->depth.smoothed);
    // Frame 1, smoothed with frame 0's history, differs from its raw depth.
    EXPECT_NE((*r)->depth.data->depthMeters.pixels, frames[1]->sceneDepth->depthMeters.pixels);

    processor_.afterSeek(1);
    device_->push(asReplayed(frames[2], 0)); // still on its way when the seek was asked for
    ASSERT_TRUE(waitUntil([&] { return processor_.counts().framesSkipped == 1; }))
        << "skipped " << processor_.counts().framesSkipped << ", processed "
        << processor_.counts().framesProcessed << ", captured " << session_->stats().framesCaptured
        << ", dropped in the slot " << session_->stats().framesDropped << ", still queued "
        << device_->pending();
    // A change now has no frame to redo: the one before the seek is gone.
    d.fog = true;
    const std::uint64_t fog = processor_.setDemand(d);
    device_->push(asReplayed(frames[1], 1)); // the frame the seek asked for
    r = processor_.waitFor(10s, any);
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->frame->sequence, 1u) << "no result of a frame decoded before the seek";
    EXPECT_EQ((*r)->frame->replay->seekGeneration, 1u);
    EXPECT_EQ((*r)->demandGeneration, fog);
    // With the history dropped, frame 1 smoothed alone is its raw depth.
    EXPECT_EQ((*r)->depth.data->depthMeters.pixels, frames[1]->sceneDepth->depthMeters.pixels);
}

// A replay that decodes a capture again with its colour (a panel asked for the video) delivers the same
// timestamp twice: that is the current frame made complete, not a new one.
TEST_F(FrameProcessorTest, TheSameCaptureDeliveredAgainIsShownButNotCountedAsNew) {
    processor_.setDemand(cloudAndPanels());
    const frame::FramePtr first = syntheticFrames(1).front();
    auto again = std::make_shared<frame::Frame>(*first);
    device_->push(first);
    ASSERT_TRUE(processor_.waitFor(10s, any));
    device_->push(again);
    const auto r = processor_.waitFor(10s, [&](const processing::ShownFrame& s) { return s.frame == again; });
    ASSERT_TRUE(r);
    EXPECT_FALSE((*r)->newFrame);
    const ProcessorCounts c = processor_.counts();
    EXPECT_EQ(c.framesProcessed, 1u);
    EXPECT_EQ(c.framesSkipped, 1u);
}

// A stage that throws (OpenCV does, on input it refuses) costs that frame's result, not the processor
// thread or the process: the failure is counted and logged once, naming the stage, and the frames after
// it are processed as before. The seam throws from the point count stage of the second frame only.
TEST(FrameProcessorFaultTest, AStageThatThrowsCostsOneFrameAndIsLoggedNamingTheStage) {
    std::vector<std::string> errors;
    std::mutex logged;
    const std::uint64_t sink = setLogSink([&](LogLevel level, const std::string& message) {
        if (level == LogLevel::Error) {
            std::lock_guard lock(logged);
            errors.push_back(message);
        }
    });
    {
        std::lock_guard lock(logged);
        errors.clear(); // the sink is first given what earlier tests in this process logged
    }
    std::atomic<int> pointCounts = 0;
    StageStats stages;
    processing::AccumulationWorker accumulation;
    FrameProcessor processor(stages, accumulation, [&](std::string_view stage) {
        if (stage == kPointCountStage && ++pointCounts == 2)
            throw std::runtime_error("injected failure");
    });
    auto device = std::make_unique<ScriptedDevice>(0.0);
    ScriptedDevice& source = *device;
    auto session = std::make_shared<devices::Session>(std::move(device));
    ASSERT_TRUE(session->start().ok());
    processor.setSession(session);
    processor.setDemand(cloudAndPanels());
    const std::vector<frame::FramePtr> frames = syntheticFrames(3);
    for (const frame::FramePtr& f : frames) {
        source.push(f);
        ASSERT_TRUE(waitUntil([&] {
            const ProcessorCounts c = processor.counts();
            return c.framesProcessed + c.failures == f->sequence + 1;
        })) << "frame "
            << f->sequence;
        if (f->sequence != 1) {
            const auto r =
                processor.waitFor(10s, [&](const processing::ShownFrame& s) { return s.frame == f; });
            ASSERT_TRUE(r) << "frame " << f->sequence << " is processed";
            EXPECT_GT((*r)->pointCount, 0u);
        }
    }
    const ProcessorCounts c = processor.counts();
    EXPECT_EQ(c.failures, 1u);
    EXPECT_EQ(c.framesProcessed, 2u);
    processor.setSession(nullptr);
    removeLogSink(sink);
    std::lock_guard lock(logged);
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_NE(errors[0].find("point count: injected failure"), std::string::npos) << errors[0];
}

// The instrument's frame counts add up for a paced source and a consumer slower than it: every delivered
// frame is shown or dropped, and at any moment at most three are on their way (the session's mailbox, the
// processor's hands, the result slot).
// Switching sources as the Instrument does (no session, then the new one) while the processor is busy, so
// that its next work item carries both: with the new source still silent, nothing of the old source's last
// frame is processed or shown for it. The seam holds the processor inside the fog stage meanwhile.
TEST(FrameProcessorSwitchTest, AfterASourceSwitchTheOldSourcesFrameIsNeverShownAgain) {
    std::atomic<bool> inFog = false, release = false;
    StageStats stages;
    processing::AccumulationWorker accumulation;
    FrameProcessor processor(stages, accumulation, [&](std::string_view stage) {
        if (stage != kFogStage)
            return;
        inFog = true;
        while (!release)
            std::this_thread::sleep_for(1ms);
    });
    auto device = std::make_unique<ScriptedDevice>(0.0);
    ScriptedDevice& source = *device;
    auto old = std::make_shared<devices::Session>(std::move(device));
    ASSERT_TRUE(old->start().ok());
    processor.setSession(old);
    Demand d = cloudAndPanels();
    processor.setDemand(d);
    source.push(syntheticFrames(1));
    ASSERT_TRUE(processor.waitFor(10s, any));
    d.fog = true;
    processor.setDemand(d); // a redo of the old frame, held in its fog stage
    ASSERT_TRUE(waitUntil([&] { return inFog.load(); }));
    auto silent = std::make_shared<devices::Session>(std::make_unique<ScriptedDevice>(0.0));
    ASSERT_TRUE(silent->start().ok());
    processor.setSession(nullptr);
    processor.setSession(silent);
    release = true;
    EXPECT_FALSE(processor.waitFor(500ms, any)) << "nothing to show until the new source delivers";
    processor.setSession(nullptr);
}

TEST(InstrumentCountsTest, ShownPlusDroppedIsDeliveredWithASlowConsumer) {
    constexpr std::uint64_t kFrames = 40;
    auto device = std::make_unique<ScriptedDevice>(240.0);
    ScriptedDevice& source = *device;
    Instrument instrument(std::move(device), "scripted");
    instrument.setDemand(cloudAndPanels());
    instrument.start();
    source.push(syntheticFrames(kFrames));
    FrameCounts c;
    const bool done = waitUntil(
        [&] {
            if (auto r = instrument.update())
                instrument.presented(**r);
            c = instrument.status().frames;
            EXPECT_LE(c.shown + c.dropped, c.delivered);
            EXPECT_LE(c.delivered - c.shown - c.dropped, 3u);
            std::this_thread::sleep_for(30ms); // the slow GL frame
            return c.delivered == kFrames && c.shown + c.dropped == kFrames;
        },
        20s);
    EXPECT_TRUE(done) << "delivered " << c.delivered << ", shown " << c.shown << ", dropped " << c.dropped;
    EXPECT_GT(c.dropped, 0u);
    EXPECT_GT(c.shown, 1u);
}

} // namespace
} // namespace dc::engine::test
