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
    devices::FramePtr process(devices::FramePtr frame, const ProcessingSettings&) override {
        ++runs;
        auto copy = std::make_shared<devices::Frame>(*frame);
        copy->sequence += 100;
        return copy;
    }
    void reset() override { ++resets; }

    int runs = 0;
    int resets = 0;

private:
    bool needsCloud_;
};

devices::FramePtr frameOfSize(int w, int h) {
    auto f = std::make_shared<devices::Frame>();
    f->sceneDepth = devices::DepthData{devices::Plane<float>(w, h), {}};
    return f;
}

TEST(Pipeline, RunsAWantedStageAndTimesIt) {
    Pipeline p;
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    const auto out = p.run(frameOfSize(4, 4), {.smoothing = true}, {});
    EXPECT_EQ(s->runs, 1);
    EXPECT_EQ(out->sequence, 100u);
    ASSERT_EQ(p.lastTimings().size(), 1u);
    EXPECT_EQ(p.lastTimings()[0].name, "recording");
    EXPECT_GE(p.lastTimings()[0].milliseconds, 0.0);
}

TEST(Pipeline, SkipsStagesThatAreOffOrThatNoVisiblePanelNeeds) {
    Pipeline p;
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    const auto in = frameOfSize(4, 4);
    EXPECT_EQ(p.run(in, {.smoothing = false}, {}), in) << "switched off: the frame passes through untouched";
    Needs cloudHidden;
    cloudHidden.cloud = false;
    EXPECT_EQ(p.run(in, {.smoothing = true}, cloudHidden), in) << "nothing visible needs it";
    EXPECT_EQ(s->runs, 0);
    EXPECT_TRUE(p.lastTimings().empty());
}

TEST(Pipeline, AResolutionChangeResetsTemporalState) {
    Pipeline p;
    auto stage = std::make_unique<RecordingStage>(true);
    RecordingStage* s = stage.get();
    p.add(std::move(stage));
    p.run(frameOfSize(4, 4), {.smoothing = true}, {});
    p.run(frameOfSize(4, 4), {.smoothing = true}, {});
    EXPECT_EQ(s->resets, 1) << "the first frame starts clean";
    p.run(frameOfSize(8, 6), {.smoothing = true}, {});
    EXPECT_EQ(s->resets, 2);
}

TEST(Pipeline, DefaultPipelineDoesNotClaimStagesItLacks) {
    const Pipeline p = makeDefaultPipeline();
    EXPECT_FALSE(p.hasStage(kSmoothingStage));
    EXPECT_FALSE(p.hasStage(kUpsamplingStage));
}

} // namespace
} // namespace dc::processing
