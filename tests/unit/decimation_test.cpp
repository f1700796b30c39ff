// Decimation keeps, of each cell, the nearest sample the cloud would draw, with its own confidence, and
// places it where the cell's centre unprojects.

#include "processing/decimation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dc::processing {
namespace {

TEST(Decimation, KeepsTheNearestDrawableSampleOfEachCell) {
    // 4x2 samples, two 2x2 cells. Left cell: the nearest sample (0.5 m) has low confidence and the next
    // (0.8 m, NaN beside it) is what a Medium level draws. Right cell: nothing drawable at all.
    frame::DepthData depth{frame::Plane<float>(4, 2, 2.0f), frame::Plane<std::uint8_t>(4, 2, 2)};
    depth.depthMeters.at(0, 0) = 0.5f;
    depth.confidence.at(0, 0) = 0;
    depth.depthMeters.at(1, 1) = 0.8f;
    depth.depthMeters.at(0, 1) = std::numeric_limits<float>::quiet_NaN();
    for (int y = 0; y < 2; ++y)
        for (int x = 2; x < 4; ++x)
            depth.confidence.at(x, y) = 1;
    const frame::Intrinsics k{100.0, 100.0, 1.5, 0.5, 4, 2};

    const DecimatedDepth d = decimateNearest(depth, k, 2, frame::Confidence::High, 0.1f);
    ASSERT_EQ(d.data->depthMeters.width, 2);
    ASSERT_EQ(d.data->depthMeters.height, 1);
    EXPECT_EQ(d.data->depthMeters.at(0, 0), 0.8f);
    EXPECT_EQ(d.data->confidence.at(0, 0), 2);
    EXPECT_EQ(d.data->depthMeters.at(1, 0), 0.0f) << "no drawable sample: no point";

    const DecimatedDepth all = decimateNearest(depth, k, 2, frame::Confidence::Low, 0.1f);
    EXPECT_EQ(all.data->depthMeters.at(0, 0), 0.5f);
    EXPECT_EQ(all.data->confidence.at(0, 0), 0);
    EXPECT_EQ(all.data->depthMeters.at(1, 0), 2.0f);
}

TEST(Decimation, CellsUnprojectThroughTheirCentres) {
    frame::DepthData depth{frame::Plane<float>(640, 480, 1.0f), {}};
    const frame::Intrinsics k{500.0, 510.0, 319.5, 239.5, 640, 480};
    for (int factor : {2, 3, 4}) {
        const DecimatedDepth d = decimateNearest(depth, k, factor, frame::Confidence::Low, 0.0f);
        // Cell (7, 5) covers samples [7f, 8f) x [5f, 6f): its centre is sample 7f + (f - 1) / 2.
        const double u = 7 * factor + (factor - 1) / 2.0;
        const double v = 5 * factor + (factor - 1) / 2.0;
        EXPECT_NEAR((7 - d.intrinsics.cx) / d.intrinsics.fx, (u - k.cx) / k.fx, 1e-12) << factor;
        EXPECT_NEAR((5 - d.intrinsics.cy) / d.intrinsics.fy, (v - k.cy) / k.fy, 1e-12) << factor;
        EXPECT_EQ(d.intrinsics.width, (640 + factor - 1) / factor);
    }
}

TEST(Decimation, FootprintFactorFitsThePanel) {
    EXPECT_EQ(footprintFactor(256, 192, 640 * 480), 1);
    EXPECT_EQ(footprintFactor(1280, 720, 640 * 480), 2);
    EXPECT_EQ(footprintFactor(1280, 720, 640 * 360), 2);
    EXPECT_EQ(footprintFactor(1280, 720, 640 * 360 - 1), 3);
    EXPECT_EQ(footprintFactor(1280, 720, 0), 1) << "unknown panel size";
}

TEST(Decimation, APanelsSamplesAreTheCentresOfItsCellsWithTheirConfidence) {
    // 7x5 samples numbered by position, every 3rd: cells of 3x3 (the last column and row cut short).
    frame::DepthData depth{frame::Plane<float>(7, 5), frame::Plane<std::uint8_t>(7, 5)};
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) {
            depth.depthMeters.at(x, y) = static_cast<float>(10 * y + x);
            depth.confidence.at(x, y) = static_cast<std::uint8_t>((x + y) % 3);
        }
    depth.confidenceEstimated = true;

    const frame::DepthData sampled = sampleCellCentres(depth, 3);
    ASSERT_EQ(sampled.depthMeters.width, 3);
    ASSERT_EQ(sampled.depthMeters.height, 2);
    const int xs[] = {1, 4, 6}; // a cell's centre, or the map's last sample where the cell is cut short
    const int ys[] = {1, 4};
    for (int cy = 0; cy < 2; ++cy)
        for (int cx = 0; cx < 3; ++cx) {
            EXPECT_EQ(sampled.depthMeters.at(cx, cy), depth.depthMeters.at(xs[cx], ys[cy]))
                << cx << "," << cy;
            EXPECT_EQ(sampled.confidence.at(cx, cy), depth.confidence.at(xs[cx], ys[cy])) << cx << "," << cy;
        }
    EXPECT_TRUE(sampled.confidenceEstimated);

    depth.confidence = {};
    EXPECT_TRUE(sampleCellCentres(depth, 2).confidence.empty()) << "no confidence stays none";
}

} // namespace
} // namespace dc::processing
