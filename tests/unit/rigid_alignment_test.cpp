// The overlap consistency figure and the ICP refinement (issue 32, item 3) on two synthetic cameras at known
// poses viewing one scene: with the true transform the figure is within the scene's noise, with a 3 degree /
// 3 cm error it is clearly larger and ICP recovers the truth. Then the cases that must not run away: no
// overlap, one flat plane, empty and all-zero depth, NaN and inf samples.

#include "devices/synthetic/synthetic_scene.h"
#include "processing/rigid_alignment.h"
#include "tests/pose_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace dc::processing {
namespace {

// Turned by `degrees` about the unit `axis`, then moved by `translation`.
frame::RigidTransform motion(std::array<double, 3> axis, double degrees, std::array<double, 3> translation) {
    const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& a : axis)
        a /= length;
    const double angle = degrees * test::kDegToRad;
    const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
    const auto& [x, y, z] = axis;
    return {{t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
             t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c},
            translation};
}

frame::Pose poseOf(const frame::RigidTransform& cameraToWorld) {
    frame::Pose pose;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
            pose.cameraToWorld[static_cast<std::size_t>(c * 4 + r)] = cameraToWorld.rotation[r * 3 + c];
        pose.cameraToWorld[static_cast<std::size_t>(12 + r)] = cameraToWorld.translationMeters[r];
    }
    return pose;
}

// The transform's error against the truth: its angle (degrees) and how far it moves B's origin (mm).
struct TransformError {
    double degrees = 0.0;
    double mm = 0.0;
};
TransformError errorOf(const frame::RigidTransform& estimate, const frame::RigidTransform& truth) {
    const frame::RigidTransform e = compose(estimate, inverse(truth));
    const auto& t = e.translationMeters;
    return {rotationDegrees(e), 1000.0 * std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])};
}

// Camera B: 20 cm to A's right and turned 8 degrees back to its left, so both see the apple, the book and
// most of the desk and wall.
struct TwoCameras {
    frame::Intrinsics k = devices::SyntheticScene::cameraIntrinsics(320, 240);
    frame::Pose poseA = devices::SyntheticScene::cameraPose(0.0, false);
    frame::Pose poseB;
    frame::DepthData a, b;
    frame::Plane<float> trueA, trueB;
    frame::RigidTransform aToB;

    TwoCameras() {
        // A's camera-to-world as a transform: from A's frame into the world's (the identity pose's frame).
        const frame::RigidTransform aToWorld = relativeTransform(poseA, frame::Pose{});
        poseB = poseOf(compose(aToWorld, motion({0, 1, 0}, -8.0, {0.20, 0.0, 0.0})));
        const devices::SyntheticScene scene;
        a = scene.sensorDepth(k, poseA, 1);
        b = scene.sensorDepth(k, poseB, 2);
        trueA = scene.trueDepth(k, poseA);
        trueB = scene.trueDepth(k, poseB);
        aToB = relativeTransform(poseA, poseB);
    }
    DepthCloud cloudA() const { return {&a, k}; }
    DepthCloud cloudB() const { return {&b, k}; }
};

const TwoCameras& twoCameras() {
    static const TwoCameras cameras;
    return cameras;
}

// The scene's noise where the cameras overlap, from the ground truth alone: median |sensor - true| (mm) over
// A's samples whose true point B also sees (it projects into B's image onto B's true depth within 1 cm).
double overlapNoiseMm(const TwoCameras& c) {
    std::vector<double> errors;
    for (int y = 0; y < c.k.height; ++y)
        for (int x = 0; x < c.k.width; ++x) {
            const double z = c.trueA.at(x, y);
            const float sensed = c.a.depthMeters.at(x, y);
            if (z <= 0.0 || sensed <= 0.0f)
                continue;
            const auto p = c.aToB.apply({(x - c.k.cx) * z / c.k.fx, (y - c.k.cy) * z / c.k.fy, z});
            const int u = static_cast<int>(std::lround(c.k.fx * p[0] / p[2] + c.k.cx));
            const int v = static_cast<int>(std::lround(c.k.fy * p[1] / p[2] + c.k.cy));
            if (p[2] <= 0.0 || u < 0 || v < 0 || u >= c.k.width || v >= c.k.height ||
                std::abs(c.trueB.at(u, v) - p[2]) > 0.01)
                continue;
            errors.push_back(std::abs(sensed - z) * 1000.0);
        }
    std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2),
                     errors.end());
    return errors[errors.size() / 2];
}

// 3 degrees about a skew axis and 3 cm, applied in B's frame after the true transform.
const frame::RigidTransform kPerturbation = motion({1.0, 2.0, -1.0}, 3.0, {0.02, -0.02, 0.01});

TEST(RigidAlignment, TheTrueTransformAgreesWithinTheScenesNoise) {
    const TwoCameras& c = twoCameras();
    const double noiseMm = overlapNoiseMm(c);
    // Both maps are noisy, so the distance between them holds two samples' noise (seen along B's normal,
    // which shortens it on surfaces seen obliquely): about the noise of one sample when all is well.
    const auto start = std::chrono::steady_clock::now();
    const OverlapFigure figure = overlapConsistency(c.cloudA(), c.cloudB(), c.aToB);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("noise %.2f mm (median |sensor - true| over the overlap); figure %.2f mm over %zu of %zu "
                "(%.0f %%) in %.1f ms\n",
                noiseMm, figure.medianMm, figure.count, figure.candidates, 100.0 * figure.overlapFraction,
                ms);
    EXPECT_GT(figure.medianMm, 0.0);
    EXPECT_LE(figure.medianMm, 1.5 * noiseMm);
    EXPECT_GT(figure.overlapFraction, 0.6);
}

TEST(RigidAlignment, APerturbedTransformIsReportedAndIcpRecoversTheTruth) {
    const TwoCameras& c = twoCameras();
    const frame::RigidTransform seed = compose(kPerturbation, c.aToB);
    const OverlapFigure truth = overlapConsistency(c.cloudA(), c.cloudB(), c.aToB);
    const OverlapFigure perturbed = overlapConsistency(c.cloudA(), c.cloudB(), seed);
    EXPECT_GT(perturbed.medianMm, 3.0 * truth.medianMm);

    const auto start = std::chrono::steady_clock::now();
    const IcpResult result = refineAlignment(c.cloudA(), c.cloudB(), seed);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const TransformError error = errorOf(result.aToB, c.aToB);
    std::printf("ICP: %s in %d iterations, %.1f ms; residual %.2f -> %.2f mm; error %.4f deg %.3f mm; "
                "correction %.3f deg %.2f mm; condition %.3f; %zu inliers\n",
                toString(result.status), result.iterations, ms, result.before.medianMm, result.after.medianMm,
                error.degrees, error.mm, result.correctionDegrees, result.correctionMm, result.conditionRatio,
                result.inliers);
    ASSERT_EQ(result.status, IcpStatus::Ok);
    EXPECT_TRUE(result.converged);
    EXPECT_LE(error.degrees, 0.2);
    EXPECT_LE(error.mm, 2.0);
    // The correction undoes the perturbation.
    const TransformError undone = errorOf(result.correction, inverse(kPerturbation));
    EXPECT_LE(undone.degrees, 0.2);
    EXPECT_LE(undone.mm, 2.0);
    EXPECT_NEAR(result.correctionDegrees, 3.0, 0.2);
    EXPECT_NEAR(result.correctionMm, 30.0, 2.0);
    EXPECT_NEAR(result.before.medianMm, perturbed.medianMm, 1e-9);
    EXPECT_LE(result.after.medianMm, 1.1 * truth.medianMm);
    EXPECT_GT(result.inliers, 1000u);
}

TEST(RigidAlignment, CloudsPointingAwayHaveNoOverlapAndKeepTheSeed) {
    const TwoCameras& c = twoCameras();
    // B at A's place, looking the other way: every point of A lies behind it.
    const frame::Pose backwards =
        poseOf(compose(relativeTransform(c.poseA, frame::Pose{}), motion({0, 1, 0}, 180.0, {})));
    const frame::DepthData b = devices::SyntheticScene().sensorDepth(c.k, backwards, 3);
    const frame::RigidTransform aToB = relativeTransform(c.poseA, backwards);
    const OverlapFigure figure = overlapConsistency(c.cloudA(), {&b, c.k}, aToB);
    EXPECT_EQ(figure.count, 0u);
    EXPECT_EQ(figure.overlapFraction, 0.0);
    EXPECT_GT(figure.candidates, 0u);
    const IcpResult result = refineAlignment(c.cloudA(), {&b, c.k}, aToB);
    EXPECT_EQ(result.status, IcpStatus::TooFewPoints);
    EXPECT_EQ(result.aToB, aToB);
    EXPECT_EQ(result.correctionDegrees, 0.0);
    EXPECT_EQ(result.correctionMm, 0.0);
}

TEST(RigidAlignment, OneFlatPlaneIsDegenerateAndDoesNotSlide) {
    // A wall filling both views: moving along it or turning about its normal changes nothing, so only the
    // distance to it and its two tilts are constrained. The seed is 5 cm off along the wall and 1 cm across
    // it.
    const frame::Intrinsics k = devices::SyntheticScene::cameraIntrinsics(320, 240);
    const devices::FlatTarget wall{1.5, 0.0, 1.0};
    const frame::DepthData a = devices::flatTargetDepth(k, wall, true, 7, 1);
    const frame::DepthData b = devices::flatTargetDepth(k, wall, true, 7, 2);
    const frame::RigidTransform seed{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0.04, -0.03, 0.01}};
    const IcpResult result = refineAlignment({&a, k}, {&b, k}, seed);
    std::printf("flat wall: %s, condition %.2e, %d directions, translation %.2f %.2f %.2f mm\n",
                toString(result.status), result.conditionRatio, result.constrainedDirections,
                result.aToB.translationMeters[0] * 1e3, result.aToB.translationMeters[1] * 1e3,
                result.aToB.translationMeters[2] * 1e3);
    EXPECT_EQ(result.status, IcpStatus::Degenerate);
    EXPECT_EQ(result.constrainedDirections, 3);
    EXPECT_LT(result.conditionRatio, IcpParams{}.minConditionRatio);
    // Along the wall it stays where it was seeded; across it, it lands on the wall.
    EXPECT_NEAR(result.aToB.translationMeters[0], 0.04, 0.002);
    EXPECT_NEAR(result.aToB.translationMeters[1], -0.03, 0.002);
    EXPECT_NEAR(result.aToB.translationMeters[2], 0.0, 0.002);
    EXPECT_LT(rotationDegrees(result.aToB), 0.2);
}

TEST(RigidAlignment, EmptyOrAllZeroDepthIsReportedWithoutACrash) {
    const TwoCameras& c = twoCameras();
    const frame::DepthData empty;
    const frame::DepthData zeros{frame::Plane<float>(c.k.width, c.k.height, 0.0f), {}};
    const frame::RigidTransform seed = c.aToB;

    EXPECT_EQ(refineAlignment({&empty, c.k}, c.cloudB(), seed).status, IcpStatus::InvalidInput);
    EXPECT_EQ(refineAlignment(c.cloudA(), {nullptr, c.k}, seed).status, IcpStatus::InvalidInput);
    EXPECT_EQ(overlapConsistency({&empty, c.k}, c.cloudB(), seed).candidates, 0u);
    // Intrinsics of another size than the depth map cannot place its samples.
    EXPECT_EQ(refineAlignment({&c.a, c.k.scaledTo(160, 120)}, c.cloudB(), seed).status,
              IcpStatus::InvalidInput);

    const IcpResult fromZeros = refineAlignment({&zeros, c.k}, c.cloudB(), seed);
    EXPECT_EQ(fromZeros.status, IcpStatus::TooFewPoints);
    EXPECT_EQ(fromZeros.aToB, seed);
    const IcpResult ontoZeros = refineAlignment(c.cloudA(), {&zeros, c.k}, seed);
    EXPECT_EQ(ontoZeros.status, IcpStatus::TooFewPoints);
    EXPECT_EQ(ontoZeros.aToB, seed);
    EXPECT_EQ(overlapConsistency(c.cloudA(), {&zeros, c.k}, seed).count, 0u);

    // A seed whose rotation is not a rotation (a scale) is refused as it is.
    frame::RigidTransform scaled = seed;
    for (double& r : scaled.rotation)
        r *= 1.1;
    const IcpResult refused = refineAlignment(c.cloudA(), c.cloudB(), scaled);
    EXPECT_EQ(refused.status, IcpStatus::InvalidInput);
    EXPECT_EQ(refused.aToB, scaled);
}

TEST(RigidAlignment, NanAndInfiniteSamplesAreIgnoredLikeMissingOnes) {
    const TwoCameras& c = twoCameras();
    // The same samples spoiled with NaN and inf in one pair of maps and set to 0 in the other: the figure and
    // the refinement must be exactly those of the zeros.
    frame::DepthData badA = c.a, badB = c.b, zeroA = c.a, zeroB = c.b;
    const float spoilers[3] = {std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity()};
    for (std::size_t i = 0; i < badA.depthMeters.pixels.size(); i += 7) {
        badA.depthMeters.pixels[i] = badB.depthMeters.pixels[i] = spoilers[(i / 7) % 3];
        zeroA.depthMeters.pixels[i] = zeroB.depthMeters.pixels[i] = 0.0f;
    }
    const OverlapFigure bad = overlapConsistency({&badA, c.k}, {&badB, c.k}, c.aToB);
    const OverlapFigure zero = overlapConsistency({&zeroA, c.k}, {&zeroB, c.k}, c.aToB);
    EXPECT_GT(bad.count, 1000u);
    EXPECT_EQ(bad.count, zero.count);
    EXPECT_EQ(bad.candidates, zero.candidates);
    EXPECT_EQ(bad.medianMm, zero.medianMm);

    const frame::RigidTransform seed = compose(kPerturbation, c.aToB);
    const IcpResult badResult = refineAlignment({&badA, c.k}, {&badB, c.k}, seed);
    const IcpResult zeroResult = refineAlignment({&zeroA, c.k}, {&zeroB, c.k}, seed);
    EXPECT_EQ(badResult.status, IcpStatus::Ok);
    EXPECT_EQ(badResult.aToB, zeroResult.aToB);
    EXPECT_LE(errorOf(badResult.aToB, c.aToB).degrees, 0.2);
}

} // namespace
} // namespace dc::processing
