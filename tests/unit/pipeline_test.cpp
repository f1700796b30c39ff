#include "processing/pipeline.h"

#include <gtest/gtest.h>

namespace dc::processing {
namespace {

// A stage that records what it was asked to do, at the stage interface the processing issue fills.
class RecordingStage final : public Stage {
public:
    explicit RecordingStage(bool needsCloud) : needsCloud_(needsCloud) {}
    std::string_view name() const override { return "recording"; }
    bool wanted(const ProcessingSettings& s, const Needs& n) const override {
        return s.smoothing && (needsCloud_ ? n.cloud : n.anyDepth());
    }
    frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings&) override {
        ++runs;
        auto copy = std::make_shared<frame::Frame>(*frame);
        copy->sequence += 100;
        return copy;
    }
    void reset() override { ++resets; }

    int runs = 0;
    int resets = 0;

private:
    bool needsCloud_;
};

ProcessingSettings smoothingSetTo(bool on) {
    ProcessingSettings s;
    s.smoothing = on;
    return s;
}

frame::FramePtr frameOfSize(int w, int h) {
    auto f = std::make_shared<frame::Frame>();
    f->sceneDepth = frame::DepthData{frame::Plane<float>(w, h), {}};
    return f;
}

// A wanted stage with nothing to do for this frame (as the confidence estimate with sensor confidence).
class PassThroughStage final : public Stage {
public:
    std::string_view name() const override { return "pass-through"; }
    bool wanted(const ProcessingSettings&, const Needs&) const override { return true; }
    frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings&) override { return frame; }
};

TEST(Pipeline, ListsTheStagesThatMadeSomethingAndNotThoseThatPassedTheFrameThrough) {
    Pipeline p;
    p.add(std::make_unique<PassThroughStage>());
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    const auto out = p.run(frameOfSize(4, 4), smoothingSetTo(true), {});
    EXPECT_EQ(s->runs, 1);
    EXPECT_EQ(out->sequence, 100u);
    ASSERT_EQ(p.lastTimings().size(), 1u) << "the pass-through stage did no work worth listing";
    EXPECT_EQ(p.lastTimings()[0].name, "recording");
}

TEST(Pipeline, SkipsStagesThatAreOffOrThatNoVisiblePanelNeeds) {
    Pipeline p;
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    const auto in = frameOfSize(4, 4);
    EXPECT_EQ(p.run(in, smoothingSetTo(false), {}), in) << "switched off: the frame passes through untouched";
    Needs cloudHidden;
    cloudHidden.cloud = false;
    EXPECT_EQ(p.run(in, smoothingSetTo(true), cloudHidden), in) << "nothing visible needs it";
    EXPECT_EQ(s->runs, 0);
    EXPECT_TRUE(p.lastTimings().empty());
}

TEST(Pipeline, AResolutionChangeResetsTemporalState) {
    Pipeline p;
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    p.run(frameOfSize(4, 4), smoothingSetTo(true), {});
    p.run(frameOfSize(4, 4), smoothingSetTo(true), {});
    EXPECT_EQ(s->resets, 1) << "the first frame starts clean";
    p.run(frameOfSize(8, 6), smoothingSetTo(true), {});
    EXPECT_EQ(s->resets, 2);
}

TEST(Pipeline, DefaultPipelineHasSmoothingAndUpsampling) {
    const Pipeline p = makeDefaultPipeline();
    EXPECT_TRUE(p.hasStage(kSmoothingStage));
    EXPECT_TRUE(p.hasStage(kUpsamplingStage));
    EXPECT_FALSE(p.hasStage("no such stage"));
}

TEST(Pipeline, ShownDepthFallsBackToTheRawMap) {
    frame::Frame f;
    EXPECT_EQ(shownDepth(f, DepthSource::Smoothed), nullptr);
    f.sceneDepth = frame::DepthData{frame::Plane<float>(2, 2, 1.0f), {}};
    EXPECT_EQ(shownDepth(f, DepthSource::Smoothed), &*f.sceneDepth) << "no smoothed map: the raw one";
    EXPECT_FALSE(showsSmoothed(f, DepthSource::Smoothed));
    f.smoothedSceneDepth = frame::DepthData{frame::Plane<float>(2, 2, 1.1f), {}};
    EXPECT_EQ(shownDepth(f, DepthSource::Smoothed), &*f.smoothedSceneDepth);
    EXPECT_EQ(shownDepth(f, DepthSource::Raw), &*f.sceneDepth);
    EXPECT_TRUE(showsSmoothed(f, DepthSource::Smoothed));
}

} // namespace
} // namespace dc::processing
