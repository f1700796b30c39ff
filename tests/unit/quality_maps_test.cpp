// The Quality panel's per-pixel maps (processing/quality_maps.h): the residual of each valid sample to a
// known plane, each pixel's deviation and fill over the noise window worked out by hand, and the colours:
// transparent where a map has no value, the ramp's ends at the range's ends.

#include "processing/quality_maps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dc::processing {
namespace {

frame::Intrinsics intrinsicsOf(int width, int height) {
    frame::Intrinsics k;
    k.fx = k.fy = 100.0;
    k.cx = width / 2.0;
    k.cy = height / 2.0;
    k.width = width;
    k.height = height;
    return k;
}

frame::DepthData wall(int width, int height, float meters) {
    frame::DepthData d;
    d.depthMeters = frame::Plane<float>(width, height, meters);
    return d;
}

// A wall at 2 m facing the camera with one sample 5 mm behind it and one missing: the residual is 0 on
// the wall, +5 mm at the bump (the plane's normal points away from the camera), NaN at the missing sample
// and wherever the causes say a sample is not valid.
TEST(QualityMaps, ThePlaneResidualIsEachValidSamplesDistanceToThePlane) {
    frame::DepthData d = wall(20, 10, 2.0f);
    d.depthMeters.at(12, 5) = 2.005f;
    d.depthMeters.at(3, 3) = 0.0f;
    QualityParams params;
    params.roi = {2, 2, 14, 6};
    FillBreakdown counts;
    const auto causes = classifySamples(d, params, counts);
    const PlaneModel plane{{0.0, 0.0, 1.0}, 2.0};
    const frame::Plane<float> map = planeResidualMm(d, intrinsicsOf(20, 10), params.roi, causes, plane);
    ASSERT_EQ(map.width, 14);
    ASSERT_EQ(map.height, 6);
    EXPECT_NEAR(map.at(10, 3), 5.0f, 1e-3f) << "the bump, at (12, 5) of the image";
    EXPECT_TRUE(std::isnan(map.at(1, 1))) << "the missing sample at (3, 3)";
    EXPECT_NEAR(map.at(0, 0), 0.0f, 1e-4f);
    EXPECT_NEAR(map.at(13, 5), 0.0f, 1e-4f);
    std::size_t valued = 0;
    for (const float v : map.pixels)
        valued += std::isfinite(v);
    EXPECT_EQ(valued, counts.valid);
}

// Three frames of a 4x1 region: pixel 0 at 1.000, 1.002, 1.004 m (deviation 2 mm), pixel 1 constant,
// pixel 2 missing once (no deviation: not valid in every frame; fill 2/3), pixel 3 never measured.
TEST(QualityMaps, TheWindowsMapsAreEachPixelsDeviationAndFill) {
    QualityParams params;
    params.roi = {0, 0, 4, 1};
    params.flyingThresholdMeters = 1.0f; // pixel 1 stands out from both neighbours: no flying pixel here
    NoiseWindow window(params, 3);
    EXPECT_TRUE(window.temporalStdMapMm().empty()) << "no frame yet";
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float frames[3][4] = {
        {1.000f, 1.5f, 1.2f, nan}, {1.002f, 1.5f, 0.0f, nan}, {1.004f, 1.5f, 1.2f, nan}};
    for (const auto& f : frames) {
        frame::DepthData d = wall(4, 1, 0.0f);
        for (int x = 0; x < 4; ++x)
            d.depthMeters.at(x, 0) = f[x];
        window.add(d, std::nullopt);
    }
    const frame::Plane<float> deviation = window.temporalStdMapMm();
    ASSERT_EQ(deviation.width, 4);
    EXPECT_NEAR(deviation.at(0, 0), 2.0f, 1e-3f);
    EXPECT_NEAR(deviation.at(1, 0), 0.0f, 1e-4f);
    EXPECT_TRUE(std::isnan(deviation.at(2, 0)));
    EXPECT_TRUE(std::isnan(deviation.at(3, 0)));
    const frame::Plane<float> fill = window.fillMapPercent();
    EXPECT_FLOAT_EQ(fill.at(0, 0), 100.0f);
    EXPECT_NEAR(fill.at(2, 0), 200.0f / 3.0f, 1e-4f);
    EXPECT_FLOAT_EQ(fill.at(3, 0), 0.0f);
}

TEST(QualityMaps, ColoursSpanTheRangeAndLeaveMissingValuesTransparent) {
    frame::Plane<float> residual(3, 1);
    residual.pixels = {-2.0f, std::numeric_limits<float>::quiet_NaN(), 2.0f};
    const QualityMapImage image = colourMap(QualityMap::PlaneResidual, residual);
    EXPECT_FLOAT_EQ(image.high, 2.0f);
    EXPECT_FLOAT_EQ(image.low, -2.0f) << "a residual's range is symmetric about the plane";
    ASSERT_EQ(image.image.pixels.size(), 12u);
    const auto pixel = [&](int i) {
        const std::uint8_t* p = &image.image.pixels[static_cast<std::size_t>(i) * 4];
        return std::array<std::uint8_t, 4>{p[0], p[1], p[2], p[3]};
    };
    const auto low = mapColour(QualityMap::PlaneResidual, 0.0f),
               high = mapColour(QualityMap::PlaneResidual, 1.0f);
    EXPECT_EQ(pixel(0), (std::array<std::uint8_t, 4>{low[0], low[1], low[2], 255}));
    EXPECT_EQ(pixel(1)[3], 0) << "no value, no colour";
    EXPECT_EQ(pixel(2), (std::array<std::uint8_t, 4>{high[0], high[1], high[2], 255}));
    EXPECT_NE(low, high);

    frame::Plane<float> fill(2, 1);
    fill.pixels = {0.0f, 100.0f};
    const QualityMapImage filled = colourMap(QualityMap::FillOverWindow, fill);
    EXPECT_FLOAT_EQ(filled.low, 0.0f);
    EXPECT_FLOAT_EQ(filled.high, 100.0f);

    frame::Plane<float> empty(2, 2, std::numeric_limits<float>::quiet_NaN());
    const QualityMapImage none = colourMap(QualityMap::TemporalStd, empty);
    EXPECT_TRUE(std::isfinite(none.low) && std::isfinite(none.high) && none.high > none.low);
    for (std::size_t i = 3; i < none.image.pixels.size(); i += 4)
        EXPECT_EQ(none.image.pixels[i], 0);
}

} // namespace
} // namespace dc::processing
