// Colour-to-depth alignment (issue 29): a box 0.8 m in front of a wall at 1.5 m, its colour shifted sideways
// by a known number of pixels, reads that shift on either side of the box, in pixels and in millimetres at
// the box's depth; unseen gray neither adds colour edges nor leaves depth edges to be scored against it;
// missing measurements, a colour image without edges and an ROI without the box are errors, never NaN.

#include "processing/edge_alignment.h"
#include "processing/registration.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <string>

namespace dc::processing {
namespace {

constexpr int kWidth = 120;
constexpr int kHeight = 80;
constexpr double kFx = 100.0;
constexpr float kBoxMeters = 0.8f;
constexpr float kWallMeters = 1.5f;
// The box covers columns kBoxLeft..kBoxRight and rows kBoxTop..kBoxBottom.
constexpr int kBoxLeft = 30, kBoxRight = 69, kBoxTop = 10, kBoxBottom = 69;
// Each ROI holds 40 rows of one vertical side of the box and nothing of its top or bottom (the nearest of
// those colour edges is 10.5 px away, beyond the search), so every depth edge in it is `shift` from its own.
constexpr Roi kRightSide{60, 20, 20, 40};
constexpr Roi kLeftSide{20, 20, 20, 40};
constexpr std::size_t kSideRows = 40;

using Rgb = std::array<std::uint8_t, 3>;
constexpr Rgb kWallColour{40, 60, 80};
constexpr Rgb kBoxColour{220, 200, 170};
constexpr Rgb kUnseen{kUnseenGray, kUnseenGray, kUnseenGray};

frame::Intrinsics intrinsics() {
    return {kFx, kFx, 59.5, 39.5, kWidth, kHeight};
}

frame::Plane<float> boxDepth() {
    frame::Plane<float> depth(kWidth, kHeight, kWallMeters);
    for (int y = kBoxTop; y <= kBoxBottom; ++y)
        for (int x = kBoxLeft; x <= kBoxRight; ++x)
            depth.at(x, y) = kBoxMeters;
    return depth;
}

void paint(RgbImage& image, int left, int right, int top, int bottom, const Rgb& colour) {
    for (int y = top; y <= bottom; ++y)
        for (int x = left; x <= right; ++x)
            for (int c = 0; c < 3; ++c)
                image.pixels[(static_cast<std::size_t>(y) * kWidth + x) * 3 + c] = colour[c];
}

RgbImage plainColour(const Rgb& colour) {
    RgbImage image{kWidth, kHeight,
                   std::vector<std::uint8_t>(static_cast<std::size_t>(kWidth) * kHeight * 3)};
    paint(image, 0, kWidth - 1, 0, kHeight - 1, colour);
    return image;
}

// The box's colour moved `shiftPx` to the right of its depth.
RgbImage boxColour(int shiftPx) {
    RgbImage image = plainColour(kWallColour);
    paint(image, kBoxLeft + shiftPx, kBoxRight + shiftPx, kBoxTop, kBoxBottom, kBoxColour);
    return image;
}

double millimetresAtTheBox(double px) {
    return px * kBoxMeters / kFx * 1000.0;
}

Expected<EdgeAlignment> measure(const frame::Plane<float>& depth, const RgbImage& colour, const Roi& roi) {
    return measureEdgeAlignment(depth, colour, intrinsics(), roi);
}

// The right side's colour edge moves away from the box, the left side's into it: both read the shift, so a
// registered image reads 0 on every side rather than Canny's one-sided pixel (0 on one side, 1 on the other).
TEST(EdgeAlignment, AShiftedColourEdgeReadsItsShiftOnEitherSideInPixelsAndMillimetres) {
    for (const int shift : {0, 2, 5}) {
        for (const Roi& roi : {kRightSide, kLeftSide}) {
            SCOPED_TRACE("shift " + std::to_string(shift) + " px, ROI at x = " + std::to_string(roi.x));
            const auto a = measure(boxDepth(), boxColour(shift), roi);
            ASSERT_TRUE(a.ok()) << a.error().message;
            EXPECT_NEAR(a->medianPx, shift, 0.25);
            EXPECT_NEAR(a->meanPx, shift, 0.25);
            EXPECT_NEAR(a->medianMm, millimetresAtTheBox(shift), 0.02 * millimetresAtTheBox(shift) + 1e-9);
            EXPECT_EQ(a->depthEdgePixels, kSideRows);
            EXPECT_EQ(a->matched, kSideRows);
            EXPECT_DOUBLE_EQ(a->matchedFraction(), 1.0);
        }
    }
}

TEST(EdgeAlignment, ColourEdgesJustOutsideTheRoiCount) {
    const Roi upToTheBoxSide{60, 20, 10,
                             40}; // ends at the box's last column; its colour edge lies 5 px beyond
    const auto a = measure(boxDepth(), boxColour(5), upToTheBoxSide);
    ASSERT_TRUE(a.ok()) << a.error().message;
    EXPECT_NEAR(a->medianPx, 5.0, 0.25);
    EXPECT_EQ(a->matched, kSideRows);
}

// A gray band inside the box, 4 px from its depth edge: its border would be a colour edge nearer than the
// box's own (5 px away) and pull the median to 4.
TEST(EdgeAlignment, AnUnseenBandInsideTheBoxAddsNoColourEdge) {
    RgbImage colour = boxColour(5);
    paint(colour, kBoxRight - 8, kBoxRight - 4, 0, kHeight - 1, kUnseen);
    const auto without = measure(boxDepth(), boxColour(5), kRightSide);
    const auto with = measure(boxDepth(), colour, kRightSide);
    ASSERT_TRUE(without.ok() && with.ok()) << with.error().message;
    EXPECT_NEAR(with->medianPx, 5.0, 0.25);
    EXPECT_DOUBLE_EQ(with->medianPx, without->medianPx);
    EXPECT_DOUBLE_EQ(with->meanPx, without->meanPx);
    EXPECT_EQ(with->matched, kSideRows);
}

// The colour camera's occlusion shadow beside the silhouette, rows 20..29: the box's colour edge there is the
// shadow's border, so those depth edges (and the two rows either side) are not scored at all.
TEST(EdgeAlignment, DepthEdgesBesideUnseenColourAreNotScored) {
    RgbImage colour = boxColour(2);
    paint(colour, kBoxRight + 1, kBoxRight + 6, 20, 29, kUnseen);
    const auto a = measure(boxDepth(), colour, kRightSide);
    ASSERT_TRUE(a.ok()) << a.error().message;
    EXPECT_EQ(a->depthEdgePixels, kSideRows - 12);
    EXPECT_EQ(a->matched, kSideRows - 12);
    EXPECT_NEAR(a->medianPx, 2.0, 0.25);
    EXPECT_NEAR(a->meanPx, 2.0, 0.25);
}

TEST(EdgeAlignment, AColourImageWithoutEdgesMatchesNoDepthEdge) {
    const auto a = measure(boxDepth(), plainColour(kWallColour), kRightSide);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().message.rfind(kNotEnoughSamples, 0), 0u) << a.error().message;
    EXPECT_NE(a.error().message.find("no depth edge matched"), std::string::npos) << a.error().message;
}

// No measurement (0, NaN, inf) forms no edge, not even where it meets a measured sample.
TEST(EdgeAlignment, SamplesWithoutAMeasurementFormNoDepthEdge) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (const float none : {0.0f, nan, inf, -1.0f}) {
        SCOPED_TRACE(none);
        const auto empty = measure(frame::Plane<float>(kWidth, kHeight, none), boxColour(2), kRightSide);
        ASSERT_FALSE(empty.ok());
        EXPECT_NE(empty.error().message.find("no depth edge in the ROI"), std::string::npos)
            << empty.error().message;
        frame::Plane<float> boxInAHole = boxDepth();
        for (float& z : boxInAHole.pixels)
            if (z == kWallMeters)
                z = none;
        const auto hole = measure(boxInAHole, boxColour(2), kRightSide);
        ASSERT_FALSE(hole.ok());
        EXPECT_EQ(hole.error().message.rfind(kNotEnoughSamples, 0), 0u) << hole.error().message;
        EXPECT_NE(hole.error().message.find("no depth edge in the ROI"), std::string::npos)
            << hole.error().message;
    }
}

// A lasso around the box's right side whose bounds also hold its left side: the left side's depth edges
// (whose colour edges are in place, 0 px) are outside the lasso and not scored, so the figure is the right
// side's 2 px alone, as a rectangle around that side reads it; scored over the bounds, where most edges are
// in place, it would be 0 px.
TEST(EdgeAlignment, OnlyTheLassosSamplesAreScoredNotItsBounds) {
    RgbImage colour = plainColour(kWallColour);
    paint(colour, kBoxLeft, kBoxRight + 2, kBoxTop, kBoxBottom, kBoxColour);
    // The right side's rectangle, bridged (an edge there and back, which cancels) to a small square of wall
    // that puts the bounds' corner at (20, 2).
    const Polygon lasso{{60, 20}, {80, 20}, {80, 60}, {60, 60}, {60, 20},
                        {20, 2},  {24, 2},  {24, 4},  {20, 4},  {20, 2}};
    const Roi bounds = polygonBounds(lasso);
    ASSERT_LE(bounds.x, kBoxLeft - 1);
    const auto inLasso = measureEdgeAlignment(boxDepth(), colour, intrinsics(), bounds, lasso);
    ASSERT_TRUE(inLasso.ok()) << inLasso.error().message;
    EXPECT_EQ(inLasso->depthEdgePixels, kSideRows);
    EXPECT_NEAR(inLasso->medianPx, 2.0, 0.25);
    const auto rightSide = measure(boxDepth(), colour, kRightSide);
    ASSERT_TRUE(rightSide.ok()) << rightSide.error().message;
    EXPECT_EQ(inLasso->meanPx, rightSide->meanPx);
    const auto overBounds = measure(boxDepth(), colour, bounds);
    ASSERT_TRUE(overBounds.ok()) << overBounds.error().message;
    EXPECT_GT(overBounds->depthEdgePixels, 2 * kSideRows) << "the bounds hold the left side and the top";
    EXPECT_LT(overBounds->medianPx, 1.0);
}

TEST(EdgeAlignment, ARoiBesideTheBoxHasNoDepthEdge) {
    const auto a = measure(boxDepth(), boxColour(2), Roi{90, 10, 25, 60});
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().message.rfind(kNotEnoughSamples, 0), 0u) << a.error().message;
    EXPECT_NE(a.error().message.find("no depth edge in the ROI"), std::string::npos) << a.error().message;
}

TEST(EdgeAlignment, InputsThatDoNotFitAreRefusedInOneLine) {
    RgbImage narrow = boxColour(2);
    narrow.width -= 1;
    narrow.pixels.resize(static_cast<std::size_t>(narrow.width) * kHeight * 3);
    frame::Intrinsics otherSize = intrinsics();
    otherSize.width *= 2;
    EdgeAlignmentParams noSearch;
    noSearch.maxSearchPx = 0.0;
    const std::pair<Expected<EdgeAlignment>, const char*> cases[] = {
        {measure(boxDepth(), narrow, kRightSide), "not the depth map's size"},
        {measureEdgeAlignment(boxDepth(), boxColour(2), otherSize, kRightSide), "intrinsics"},
        {measure(boxDepth(), boxColour(2), Roi{100, 0, 30, 10}), "ROI lies outside"},
        {measureEdgeAlignment(boxDepth(), boxColour(2), intrinsics(), kRightSide, noSearch), "parameters"},
    };
    for (const auto& [result, mentions] : cases) {
        ASSERT_FALSE(result.ok()) << mentions;
        EXPECT_NE(result.error().message.find(mentions), std::string::npos) << result.error().message;
        EXPECT_EQ(result.error().message.find(kNotEnoughSamples), std::string::npos)
            << result.error().message;
        EXPECT_EQ(result.error().message.find('\n'), std::string::npos) << result.error().message;
    }
}

} // namespace
} // namespace dc::processing
