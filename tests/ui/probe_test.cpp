#include "ui/probe.h"

#include "devices/synthetic/synthetic_device.h"
#include "processing/registration.h"
#include "tests/small_rig.h"

#include <gtest/gtest.h>

namespace dc::ui {
namespace {

TEST(Probe, APointTheColourCameraCannotSeeIsReadOutAsNotSeen) {
    frame::DepthData depth{frame::Plane<float>(4, 2, 1.5f), {}};
    depth.depthMeters.at(3, 1) = 0.0f;
    frame::Plane<std::uint8_t> seen(4, 2, 1);
    seen.at(0, 0) = 0;
    seen.at(3, 1) = 0;
    const ProbeSource source{&depth, {100.0, 100.0, 2.0, 1.0, 4, 2}, &seen};

    EXPECT_FALSE(probeAt(source, 0, 0)->seenByColour);
    EXPECT_TRUE(probeAt(source, 1, 0)->seenByColour);
    EXPECT_TRUE(probeAt(source, 3, 1)->seenByColour) << "no depth: no point, nothing to colour";

    const ProbeSource oneCamera{&depth, {100.0, 100.0, 2.0, 1.0, 4, 2}, nullptr};
    EXPECT_TRUE(probeAt(oneCamera, 0, 0)->seenByColour);
    EXPECT_STREQ(kNotSeenByColour, "not seen by the colour camera");
}

// The readout names the frame sampled: its sequence, and the driver's where a live camera gave one.
TEST(Probe, TheReadoutNamesTheFramesSequenceAndTheDriversWhereKnown) {
    auto f = std::make_shared<frame::Frame>();
    f->sequence = 42;
    f->sceneDepth = frame::DepthData{frame::Plane<float>(4, 2, 1.5f), {}};
    const frame::Intrinsics intrinsics{100.0, 100.0, 2.0, 1.0, 4, 2};
    const ProbeSource replayed{&*f->sceneDepth, intrinsics, nullptr, f.get()};
    EXPECT_EQ(probeAt(replayed, 1, 1)->frameSequence, 42u);
    EXPECT_FALSE(probeAt(replayed, 1, 1)->driverSequence);
    f->timing.depth.driverSequence = 1234u;
    EXPECT_EQ(probeAt(replayed, 1, 1)->driverSequence, 1234u);
    const ProbeSource noFrame{&*f->sceneDepth, intrinsics, nullptr};
    EXPECT_FALSE(probeAt(noFrame, 1, 1)->frameSequence);
}

// The line the tooltip shows: the driver's sequence and the exposure only where the frame carries them,
// never a 0 standing in for an unknown.
TEST(Probe, TheReadoutShowsTheSequenceAndExposureOnlyWhereTheFrameCarriesThem) {
    auto f = std::make_shared<frame::Frame>();
    f->sequence = 42;
    f->sceneDepth = frame::DepthData{frame::Plane<float>(4, 2, 1.5f), {}};
    const ProbeSource source{&*f->sceneDepth, {100.0, 100.0, 2.0, 1.0, 4, 2}, nullptr, f.get()};
    EXPECT_EQ(frameReadout(*probeAt(source, 1, 1)), "frame 42") << "a frame without driver timing";

    f->timing.depth.driverSequence = 1234u;
    EXPECT_EQ(frameReadout(*probeAt(source, 1, 1)), "frame 42, seq 1234");

    f->timing.depth.exposureUs = 8500u;
    EXPECT_EQ(probeAt(source, 1, 1)->exposureUs, 8500u);
    EXPECT_EQ(frameReadout(*probeAt(source, 1, 1)), "frame 42, seq 1234, exposure 8500 \u00b5s");

    f->timing.depth.driverSequence.reset();
    EXPECT_EQ(frameReadout(*probeAt(source, 1, 1)), "frame 42, exposure 8500 \u00b5s");

    const ProbeSource noFrame{&*f->sceneDepth, {100.0, 100.0, 2.0, 1.0, 4, 2}, nullptr};
    EXPECT_EQ(frameReadout(*probeAt(noFrame, 1, 1)), "") << "nothing names a frame it was not given";
}

// The camera's own account of the frame from its metadata node (its frame counter, gain and laser power),
// each only where it gave it: none of them, no line.
TEST(Probe, TheReadoutShowsTheCamerasFrameCounterGainAndLaserPowerOnlyWhereKnown) {
    auto f = std::make_shared<frame::Frame>();
    f->sequence = 42;
    f->sceneDepth = frame::DepthData{frame::Plane<float>(4, 2, 1.5f), {}};
    const ProbeSource source{&*f->sceneDepth, {100.0, 100.0, 2.0, 1.0, 4, 2}, nullptr, f.get()};
    f->timing.depthMetadata.ptsTicks = 123456u; // clocks are not part of the readout
    EXPECT_EQ(cameraReadout(*probeAt(source, 1, 1)), "") << "a camera that said none of them";

    f->timing.depthMetadata.frameCounter = 4242u;
    f->timing.depthMetadata.gain = 16u;
    f->timing.depthMetadata.laserPowerMw = 150u;
    const Probe all = *probeAt(source, 1, 1);
    EXPECT_EQ(all.cameraFrameCounter, 4242u);
    EXPECT_EQ(all.gain, 16u);
    EXPECT_EQ(all.laserPowerMw, 150u);
    EXPECT_EQ(cameraReadout(all), "camera frame 4242, gain 16, laser 150 mW");
    EXPECT_EQ(frameReadout(all), "frame 42") << "the driver's line is unchanged";

    f->timing.depthMetadata.frameCounter.reset();
    f->timing.depthMetadata.laserPowerMw = 0u;
    EXPECT_EQ(cameraReadout(*probeAt(source, 1, 1)), "gain 16, laser 0 mW") << "a laser that is off says 0";

    f->timing.depthMetadata.gain.reset();
    f->timing.depthMetadata.laserPowerMw.reset();
    f->timing.depthMetadata.frameCounter = 7u;
    EXPECT_EQ(cameraReadout(*probeAt(source, 1, 1)), "camera frame 7");

    const ProbeSource noFrame{&*f->sceneDepth, {100.0, 100.0, 2.0, 1.0, 4, 2}, nullptr};
    EXPECT_EQ(cameraReadout(*probeAt(noFrame, 1, 1)), "") << "nothing from a frame it was not given";
}

// Points the GPU coloured come with no seen mask: the probe asks the frame's rig about the one sample.
TEST(Probe, WithoutAMaskTheRigDecidesForTheProbedSample) {
    devices::SyntheticDevice device(dc::test::smallRigConfig());
    ASSERT_TRUE(device.open());
    const frame::FramePtr frame = device.makeFrame(0, 0.0);
    const frame::DepthData& depth = *frame->sceneDepth;
    const ProbeSource source{&depth, frame->depthIntrinsics(), nullptr, frame.get()};
    int seen = 0, unseen = 0;
    for (int u = 0; u < depth.depthMeters.width; u += 7) {
        const std::optional<Probe> probe = probeAt(source, u, 60);
        ASSERT_TRUE(probe);
        if (probe->depthMeters <= 0.0f)
            continue;
        EXPECT_EQ(probe->seenByColour,
                  processing::sampleSeenByColour(*frame, depth.depthMeters, frame->depthIntrinsics(), u, 60));
        (probe->seenByColour ? seen : unseen) += 1;
    }
    // The colour camera sees about the middle half of the depth camera's wider view.
    EXPECT_GT(seen, 5);
    EXPECT_GT(unseen, 5);
}

} // namespace
} // namespace dc::ui
