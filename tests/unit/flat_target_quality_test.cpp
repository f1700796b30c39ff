// The depth-quality figures on the synthetic camera's flat target (issue 29): a wall at a known distance and
// tilt with known depth noise gives back its distance, angle, plane-fit RMS and temporal noise, and a wall so
// steep that part of it lies beyond the sensor's range has exactly the fill rate its geometry gives.

#include "devices/synthetic/synthetic_device.h"
#include "processing/depth_quality.h"
#include "tests/pose_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace dc::processing {
namespace {

devices::SyntheticDevice openTarget(const devices::FlatTarget& target, bool noise = true) {
    devices::SyntheticConfig config;
    config.depthWidth = 640;
    config.depthHeight = 480;
    config.paced = false;
    config.noise = noise;
    config.flatTarget = target;
    return devices::SyntheticDevice(config);
}

// The RMS that depth noise of `sigma` along z leaves perpendicular to the plane over the ROI: a sample moved
// by e along its ray (x', y', 1) moves e (n . ray) off the plane. The robust fit keeps what lies within 3
// sigma, which leaves a Gaussian's deviation times 0.9866.
double expectedPlaneRmsMeters(const frame::Intrinsics& k, const Roi& roi, double tiltDeg, double sigma) {
    const double nx = std::sin(tiltDeg * test::kDegToRad), nz = std::cos(tiltDeg * test::kDegToRad);
    double sum = 0.0;
    for (int y = roi.y; y < roi.y + roi.height; ++y)
        for (int x = roi.x; x < roi.x + roi.width; ++x) {
            const double along = nx * (x - k.cx) / k.fx + nz;
            sum += along * along;
        }
    return sigma * std::sqrt(sum / (static_cast<double>(roi.width) * roi.height)) * 0.9866;
}

TEST(FlatTarget, TheFiguresGiveBackTheWallsDistanceTiltAndNoise) {
    const devices::FlatTarget target{1.5, 10.0, 1.0};
    devices::SyntheticDevice device = openTarget(target);
    ASSERT_TRUE(device.open());
    const frame::Intrinsics k = device.makeFrame(0, 0.0)->depthIntrinsics();
    QualityParams params;
    params.roi = centredRoi(k.width, k.height, 40.0);
    constexpr int kFrames = 30;
    NoiseWindow window(params, kFrames);
    const double expectedRmsMm = expectedPlaneRmsMeters(k, params.roi, target.tiltDegrees, 1e-3) * 1000.0;
    for (int i = 0; i < kFrames; ++i) {
        const frame::FramePtr f = device.makeFrame(static_cast<std::uint64_t>(i), i / 30.0);
        const auto q = measureFrameQuality(*f->sceneDepth, k, params);
        ASSERT_TRUE(q.ok()) << q.error().message;
        ASSERT_TRUE(q->plane.has_value()) << q->planeError;
        EXPECT_EQ(q->fill.valid, q->fill.roiSamples) << "frame " << i;
        EXPECT_NEAR(q->plane->distanceMm, 1500.0, 0.5) << "frame " << i;
        EXPECT_NEAR(q->plane->angleDeg, 10.0, 0.1) << "frame " << i;
        EXPECT_NEAR(q->plane->planeFitRmsMm, expectedRmsMm, 0.03 * expectedRmsMm) << "frame " << i;
        window.add(*f->sceneDepth, q->causes, q->plane->planeFitRmsMm);
    }
    // The median of 30-sample standard deviations is 0.9885 sigma (chi with 29 degrees of freedom).
    const auto temporal = window.temporalNoiseMm();
    ASSERT_TRUE(temporal.ok()) << temporal.error().message;
    EXPECT_NEAR(*temporal, 0.9885 * target.noiseMm, 0.05 * target.noiseMm);
}

TEST(FlatTarget, AWallPartlyBeyondTheRangeFillsExactlyWhatItsGeometryGives) {
    const devices::FlatTarget target{1.0, -80.0, 0.0};
    devices::SyntheticDevice device = openTarget(target, false);
    ASSERT_TRUE(device.open());
    const frame::FramePtr f = device.makeFrame(0, 0.0);
    const frame::Intrinsics k = f->depthIntrinsics();
    const double nx = std::sin(target.tiltDegrees * test::kDegToRad),
                 nz = std::cos(target.tiltDegrees * test::kDegToRad);
    std::size_t inRange = 0;
    for (int y = 0; y < k.height; ++y)
        for (int x = 0; x < k.width; ++x) {
            const double along = nx * (x - k.cx) / k.fx + nz;
            inRange += along > 0.0 && target.distanceMeters * nz / along <= 5.0;
        }
    ASSERT_GT(inRange, 0u);
    ASSERT_LT(inRange, static_cast<std::size_t>(k.width) * k.height) << "some of the wall lies beyond 5 m";
    QualityParams params;
    params.roi = {0, 0, k.width, k.height};
    const auto q = measureFrameQuality(*f->sceneDepth, k, params);
    ASSERT_TRUE(q.ok()) << q.error().message;
    EXPECT_EQ(q->fill.valid, inRange);
    EXPECT_EQ(q->fill.noMeasurement, q->fill.roiSamples - inRange);
    ASSERT_TRUE(q->plane.has_value()) << q->planeError;
    EXPECT_NEAR(q->plane->angleDeg, 80.0, 0.01);
    EXPECT_NEAR(q->plane->distanceMm, 1000.0, 0.5);
}

} // namespace
} // namespace dc::processing
