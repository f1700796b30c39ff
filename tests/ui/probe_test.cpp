#include "ui/probe.h"

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

} // namespace
} // namespace dc::ui
