// Depth quality figures (issue 29): a noisy tilted plane gives back its distance, angle and noise; gross
// outliers do not move the robust fit; DQT's figures on data small enough to work out by hand; every cause of
// a missing sample counted exactly; extreme and empty input gives finite figures or a clear error.

#include "processing/depth_quality.h"
#include "tests/pose_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <vector>

namespace dc::processing {
namespace {

// A plane crossing the optical axis at distanceMeters, its normal tilted by angleDeg about the y axis,
// sampled uniformly across +-0.3 distance sideways, each point moved along the normal by N(0, sigma).
std::vector<Point3d> noisyPlane(double distanceMeters, double angleDeg, double sigmaMeters, int count,
                                unsigned seed) {
    const double s = std::sin(angleDeg * test::kDegToRad), c = std::cos(angleDeg * test::kDegToRad);
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> side(-0.3 * distanceMeters, 0.3 * distanceMeters);
    std::normal_distribution<double> noise(0.0, sigmaMeters);
    std::vector<Point3d> points;
    for (int i = 0; i < count; ++i) {
        const double x = side(random), y = side(random);
        const double z = (distanceMeters * c - s * x) / c;
        const double e = noise(random);
        points.push_back({x + e * s, y, z + e * c});
    }
    return points;
}

TEST(DepthQuality, RecoversDistanceAngleAndNoiseOfATiltedPlane) {
    const double sigma = 0.002;
    const std::vector<Point3d> points = noisyPlane(1.5, 20.0, sigma, 40000, 1);
    const auto fit = fitPlaneRobust(points);
    ASSERT_TRUE(fit.ok()) << fit.error().message;
    const auto distance = distanceAlongOpticalAxis(fit->plane);
    ASSERT_TRUE(distance.ok());
    EXPECT_NEAR(*distance, 1.5, 0.0005);
    EXPECT_NEAR(angleToOpticalAxisDegrees(fit->plane), 20.0, 0.1);
    EXPECT_NEAR(fit->rmsMeters, sigma, 0.03 * sigma);
    EXPECT_GT(fit->inlierFraction, 0.99);
}

TEST(DepthQuality, GrossOutliersMoveTheLeastSquaresFitButNotTheRobustOne) {
    std::vector<Point3d> points = noisyPlane(2.0, 30.0, 0.002, 20000, 2);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> nearer(0.05, 0.5);
    for (std::size_t i = 0; i < points.size(); i += 5) {
        const double f = 1.0 - nearer(random) / points[i].z; // along the pixel's ray, toward the camera
        points[i] = {points[i].x * f, points[i].y * f, points[i].z * f};
    }
    const auto robust = fitPlaneRobust(points);
    ASSERT_TRUE(robust.ok());
    const auto plain = fitPlaneLeastSquares(points);
    ASSERT_TRUE(plain.ok());
    EXPECT_NEAR(*distanceAlongOpticalAxis(robust->plane), 2.0, 0.001);
    EXPECT_GT(std::abs(*distanceAlongOpticalAxis(*plain) - 2.0), 0.01);
    EXPECT_NEAR(robust->inlierFraction, 0.8, 0.01);
}

// A 10 x 20 grid at z = 1 +- 1 mm in a checkerboard (its residual pattern is orthogonal to 1, x and y, so
// the least-squares plane is exactly z = 1), plus two points at the grid's centroid 50 mm in front and
// behind: 202 points, floor(1.01) = 1 trimmed from each end removes exactly those two.
TEST(DepthQuality, DqtRmsTrimsHalfAPercentFromEachEnd) {
    std::vector<Point3d> points;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 10; ++i)
            points.push_back({0.01 * i, 0.01 * j, 1.0 + ((i + j) % 2 ? 0.001 : -0.001)});
    points.push_back({0.045, 0.095, 1.05});
    points.push_back({0.045, 0.095, 0.95});
    const auto plane = fitPlaneLeastSquares(points);
    ASSERT_TRUE(plane.ok());
    EXPECT_NEAR(plane->normal[2], 1.0, 1e-12);
    EXPECT_NEAR(plane->offsetMeters, 1.0, 1e-12);
    const auto dqt = dqtPlaneFitRms(points);
    ASSERT_TRUE(dqt.ok());
    EXPECT_NEAR(*dqt, 0.001, 1e-9);
}

// DQT's trimmed RMS by its definition: every residual sorted, both ends dropped, the rest's RMS.
double sortedTrimRms(const std::vector<Point3d>& points) {
    const auto plane = fitPlaneLeastSquares(points);
    std::vector<double> residuals;
    for (const Point3d& p : points)
        residuals.push_back(plane->signedDistance(p));
    std::sort(residuals.begin(), residuals.end());
    const auto trim = static_cast<std::size_t>(std::floor(0.005 * static_cast<double>(points.size())));
    double sum = 0.0;
    for (std::size_t i = trim; i < residuals.size() - trim; ++i)
        sum += residuals[i] * residuals[i];
    return std::sqrt(sum / static_cast<double>(residuals.size() - 2 * trim));
}

// The trim finds its ends without sorting every residual; layouts that stress that search give the sorted
// definition's answer: far outliers that squeeze the inliers into a few of its bins, ties across the
// trim's edge, every residual on one side of the plane but one, and a noise-free plane.
TEST(DepthQuality, DqtRmsEqualsTheSortedDefinitionOnHardLayouts) {
    std::mt19937_64 random(7);
    std::normal_distribution<double> noise(0.0, 0.001);
    const auto grid = [&](const std::function<double(int, int)>& z) {
        std::vector<Point3d> points;
        for (int j = 0; j < 300; ++j)
            for (int i = 0; i < 400; ++i)
                points.push_back({0.001 * i, 0.001 * j, z(i, j)});
        return points;
    };
    const std::vector<std::vector<Point3d>> layouts{
        grid([&](int i, int) { return 1.0 + noise(random) + (i % 5 == 0 ? 3.0 : 0.0); }),
        grid([&](int i, int j) { return 1.0 + 0.002 * ((i * 7 + j * 3) % 4); }),
        grid([&](int i, int j) { return 1.0 + (i == 17 && j == 5 ? 100.0 : 1e-6 * ((i + j) % 2)); }),
        grid([&](int i, int j) { return 1.0 + 0.01 * i + 0.02 * j; }),
        grid([&](int, int) { return 2.0 + noise(random); })};
    for (std::size_t k = 0; k < layouts.size(); ++k) {
        const auto dqt = dqtPlaneFitRms(layouts[k]);
        ASSERT_TRUE(dqt.ok()) << "layout " << k;
        const double expected = sortedTrimRms(layouts[k]);
        EXPECT_NEAR(*dqt, expected, 1e-9 * std::max(expected, 1e-6)) << "layout " << k;
    }
}

TEST(DepthQuality, ZAccuracyIsTheRelativeErrorOfTheDistance) {
    EXPECT_NEAR(zAccuracyPercent(1.002, 1.0), 0.2, 1e-9);
    EXPECT_NEAR(zAccuracyPercent(0.995, 1.0), -0.5, 1e-9);
}

// f B = 100 px x 0.05 m = 5 px m against the plane z = 1: a point measured at 1.25 m has disparity 4 px
// instead of 5, one at 5/6 m has 6 px: errors of +1 and -1 px, RMS 1 px.
TEST(DepthQuality, SubpixelRmsIsTheDisparityErrorAgainstThePlane) {
    const PlaneModel plane{{0.0, 0.0, 1.0}, 1.0};
    const std::vector<Point3d> points{{0.0, 0.0, 1.25}, {0.1 * 5.0 / 6.0, 0.0, 5.0 / 6.0}};
    const auto rms = subpixelRms(points, plane, 100.0, 0.05);
    ASSERT_TRUE(rms.ok());
    EXPECT_NEAR(*rms, 1.0, 1e-12);
    EXPECT_FALSE(subpixelRms(points, plane, 100.0, 0.0).ok());
}

frame::Intrinsics intrinsics(int w, int h) {
    return {120.0, 120.0, (w - 1) / 2.0, (h - 1) / 2.0, w, h};
}

frame::DepthData flat(int w, int h, float meters) {
    frame::DepthData d;
    d.depthMeters = frame::Plane<float>(w, h, meters);
    d.confidence = frame::Plane<std::uint8_t>(w, h, 2);
    return d;
}

struct CauseCase {
    const char* name;
    std::function<void(frame::DepthData&)> make;
    FillBreakdown expected;
};

TEST(DepthQuality, EachCauseOfAMissingSampleIsCountedExactly) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    auto none = [&](frame::DepthData& d) {
        d.depthMeters.at(1, 1) = 0.0f;
        d.depthMeters.at(3, 1) = nan;
        d.depthMeters.at(5, 1) = inf;
    };
    auto range = [](frame::DepthData& d) {
        d.depthMeters.at(1, 3) = 0.3f;
        d.depthMeters.at(5, 3) = 10.0f;
    };
    auto confidence = [](frame::DepthData& d) { d.confidence.at(3, 5) = 0; };
    auto flying = [](frame::DepthData& d) {
        d.depthMeters.at(1, 5) = 1.5f;
        d.depthMeters.at(5, 5) = 0.9f;
    };
    const CauseCase cases[] = {
        {"no measurement", none, {49, 46, 3, 0, 0, 0}},
        {"out of range", range, {49, 47, 0, 2, 0, 0}},
        {"low confidence", confidence, {49, 48, 0, 0, 1, 0}},
        {"flying", flying, {49, 47, 0, 0, 0, 2}},
        {"all",
         [&](frame::DepthData& d) {
             none(d);
             range(d);
             confidence(d);
             flying(d);
         },
         {49, 41, 3, 2, 1, 2}},
    };
    QualityParams params;
    params.roi = {0, 0, 7, 7};
    params.nearMeters = 0.5f;
    params.farMeters = 5.0f;
    params.minConfidence = frame::Confidence::Medium;
    for (const CauseCase& c : cases) {
        frame::DepthData d = flat(7, 7, 1.0f);
        c.make(d);
        FillBreakdown got;
        classifySamples(d, params, got);
        EXPECT_EQ(got.roiSamples, c.expected.roiSamples) << c.name;
        EXPECT_EQ(got.valid, c.expected.valid) << c.name;
        EXPECT_EQ(got.noMeasurement, c.expected.noMeasurement) << c.name;
        EXPECT_EQ(got.outOfRange, c.expected.outOfRange) << c.name;
        EXPECT_EQ(got.lowConfidence, c.expected.lowConfidence) << c.name;
        EXPECT_EQ(got.flyingPixel, c.expected.flyingPixel) << c.name;
        EXPECT_DOUBLE_EQ(got.fillRate(), static_cast<double>(c.expected.valid) / 49.0) << c.name;
    }
}

TEST(DepthQuality, ASlantedSurfaceIsNotFlying) {
    frame::DepthData d = flat(7, 7, 1.0f);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 7; ++x)
            d.depthMeters.at(x, y) = 1.0f + 0.2f * static_cast<float>(x + y);
    QualityParams params;
    params.roi = {0, 0, 7, 7};
    FillBreakdown got;
    classifySamples(d, params, got);
    EXPECT_EQ(got.valid, 49u);
}

// The depth a camera with intrinsics k sees of a plane crossing its axis at distance, tilted by angleDeg:
// 0 where the pixel's ray misses the plane in front.
frame::DepthData planeDepth(const frame::Intrinsics& k, double distance, double angleDeg) {
    const double s = std::sin(angleDeg * test::kDegToRad), c = std::cos(angleDeg * test::kDegToRad);
    frame::DepthData d = flat(k.width, k.height, 0.0f);
    for (int y = 0; y < k.height; ++y) {
        for (int x = 0; x < k.width; ++x) {
            const double along = s * (x - k.cx) / k.fx + c;
            d.depthMeters.at(x, y) = along > 0.0 ? static_cast<float>(distance * c / along) : 0.0f;
        }
    }
    return d;
}

void expectFiniteOrNotEnough(const FrameQuality& q, const char* name) {
    EXPECT_TRUE(std::isfinite(q.fill.fillRate())) << name;
    if (!q.plane) {
        EXPECT_NE(q.planeError.find(kNotEnoughSamples), std::string::npos) << name << ": " << q.planeError;
        return;
    }
    const PlaneFigures& f = *q.plane;
    for (double v : {f.distanceMm, f.angleDeg, f.planeFitRmsMm, f.planeFitRmsPercent, f.inlierFraction,
                     f.dqtPlaneFitRmsMm, f.zAccuracyPercent.value_or(0.0), f.subpixelRms.value_or(0.0)})
        EXPECT_TRUE(std::isfinite(v)) << name;
}

TEST(DepthQuality, ExtremePlanesGiveFiniteFigures) {
    const frame::Intrinsics k = intrinsics(160, 120);
    QualityParams params;
    params.roi = centredRoi(160, 120, 50.0);
    params.groundTruthMeters = 1.0;
    params.baselineMeters = 0.05;
    const struct {
        double distance, angle;
    } cases[] = {{0.1, 0.0}, {20.0, 0.0}, {0.1, 85.0}, {20.0, 85.0}, {1.0, 60.0}};
    for (const auto& c : cases) {
        const auto q = measureFrameQuality(planeDepth(k, c.distance, c.angle), k, params);
        ASSERT_TRUE(q.ok()) << q.error().message;
        ASSERT_TRUE(q->plane.has_value()) << q->planeError;
        expectFiniteOrNotEnough(*q, "extreme plane");
        EXPECT_NEAR(q->plane->distanceMm, c.distance * 1000.0, c.distance * 1000.0 * 1e-3);
        EXPECT_NEAR(q->plane->angleDeg, c.angle, 0.05);
    }
}

TEST(DepthQuality, FewOrNoValidSamplesGiveTheNotEnoughError) {
    const frame::Intrinsics k = intrinsics(16, 12);
    QualityParams params;
    params.roi = {0, 0, 16, 12};
    params.groundTruthMeters = 1.0;
    params.baselineMeters = 0.05;

    frame::DepthData three = flat(16, 12, 0.0f);
    three.depthMeters.at(2, 2) = three.depthMeters.at(10, 3) = three.depthMeters.at(5, 9) = 1.0f;
    const auto q3 = measureFrameQuality(three, k, params);
    ASSERT_TRUE(q3.ok());
    ASSERT_TRUE(q3->plane.has_value()) << q3->planeError;
    expectFiniteOrNotEnough(*q3, "three samples");
    EXPECT_NEAR(q3->plane->distanceMm, 1000.0, 1e-3);
    EXPECT_NEAR(*q3->plane->zAccuracyPercent, 0.0, 1e-6);

    frame::DepthData collinear = flat(16, 12, 0.0f);
    collinear.depthMeters.at(2, 2) = collinear.depthMeters.at(6, 2) = collinear.depthMeters.at(10, 2) = 1.0f;
    const auto ql = measureFrameQuality(collinear, k, params);
    ASSERT_TRUE(ql.ok());
    EXPECT_FALSE(ql->plane.has_value());
    expectFiniteOrNotEnough(*ql, "collinear samples");

    const auto q0 = measureFrameQuality(flat(16, 12, 0.0f), k, params);
    ASSERT_TRUE(q0.ok());
    EXPECT_FALSE(q0->plane.has_value());
    EXPECT_EQ(q0->fill.fillRate(), 0.0);
    expectFiniteOrNotEnough(*q0, "no valid sample");

    const auto qMax = measureFrameQuality(flat(16, 12, 65.535f), k, params);
    ASSERT_TRUE(qMax.ok());
    ASSERT_TRUE(qMax->plane.has_value()) << qMax->planeError;
    expectFiniteOrNotEnough(*qMax, "65.535 m everywhere");
    EXPECT_NEAR(qMax->plane->distanceMm, 65535.0, 0.01);

    params.roi = {10, 0, 16, 12};
    EXPECT_FALSE(measureFrameQuality(flat(16, 12, 1.0f), k, params).ok());
}

TEST(DepthQuality, ZAccuracyOfAFlatTargetAgainstGroundTruth) {
    const frame::Intrinsics k = intrinsics(40, 30);
    QualityParams params;
    params.roi = centredRoi(40, 30, 50.0);
    params.groundTruthMeters = 1.0;
    const auto q = measureFrameQuality(flat(40, 30, 1.002f), k, params);
    ASSERT_TRUE(q.ok() && q->plane.has_value());
    EXPECT_NEAR(*q->plane->zAccuracyPercent, 0.2, 1e-4);
    EXPECT_FALSE(q->plane->subpixelRms.has_value());
}

// sigmaZ = z^2 sigmaD / (f B): 2 m, 0.08 px, 640 px x 0.05 m = 4 x 0.08 / 32 = 0.01 m. A flat target at
// 2 m reads it at its fitted distance once a baseline is known, and not without one.
TEST(DepthQuality, ExpectedStereoNoiseIsTheDisparityModelAtTheMeasuredDistance) {
    EXPECT_NEAR(expectedStereoNoiseMeters(2.0, 640.0, 0.05, 0.08), 0.01, 1e-15);
    EXPECT_NEAR(expectedStereoNoiseMeters(4.0, 640.0, 0.05, 0.08), 0.04, 1e-15) << "quadratic in distance";
    const frame::Intrinsics k = intrinsics(40, 30);
    QualityParams params;
    params.roi = centredRoi(40, 30, 50.0);
    const auto without = measureFrameQuality(flat(40, 30, 2.0f), k, params);
    ASSERT_TRUE(without.ok() && without->plane.has_value());
    EXPECT_FALSE(without->plane->expectedNoiseMm.has_value());
    params.baselineMeters = 0.05;
    params.designSubpixelRms = 0.1;
    const auto with = measureFrameQuality(flat(40, 30, 2.0f), k, params);
    ASSERT_TRUE(with.ok() && with->plane.has_value());
    ASSERT_TRUE(with->plane->expectedNoiseMm.has_value());
    const double z = with->plane->distanceMm / 1000.0;
    EXPECT_NEAR(*with->plane->expectedNoiseMm, 1000.0 * z * z * 0.1 / (k.fx * 0.05), 1e-9);
}

// The overlay shows each missing sample in its cause's colour, opaque, and lets every valid one through.
TEST(DepthQuality, TheCauseOverlayColoursEachMissingSampleByItsCause) {
    const std::vector<SampleCause> causes{SampleCause::Valid,       SampleCause::NoMeasurement,
                                          SampleCause::OutOfRange,  SampleCause::LowConfidence,
                                          SampleCause::FlyingPixel, SampleCause::Valid};
    const RgbaImage overlay = causeOverlay(causes, 3, 2);
    ASSERT_EQ(overlay.width, 3);
    ASSERT_EQ(overlay.height, 2);
    ASSERT_EQ(overlay.pixels.size(), 24u);
    std::set<std::array<std::uint8_t, 3>> colours;
    for (std::size_t i = 0; i < causes.size(); ++i) {
        const std::uint8_t* p = &overlay.pixels[i * 4];
        if (causes[i] == SampleCause::Valid) {
            EXPECT_EQ(p[3], 0) << "sample " << i;
            continue;
        }
        EXPECT_EQ(p[3], 255) << "sample " << i;
        const auto rgb = causeColour(causes[i]);
        EXPECT_EQ((std::array<std::uint8_t, 3>{p[0], p[1], p[2]}), rgb) << "sample " << i;
        colours.insert(rgb);
    }
    EXPECT_EQ(colours.size(), 4u) << "every cause has a colour of its own";
    EXPECT_TRUE(causeOverlay(causes, 4, 2).empty()) << "causes that are not width x height";
}

TEST(DepthQuality, CentredRoiIsDqtsPercentOfEachSide) {
    EXPECT_EQ(centredRoi(1280, 720, 40.0), (Roi{384, 216, 512, 288}));
    EXPECT_EQ(centredRoi(10, 10, 0.0), (Roi{4, 4, 1, 1}));
    EXPECT_EQ(centredRoi(10, 10, 100.0), (Roi{0, 0, 10, 10}));
}

// 10 frames of 20 mm noise, then 30 of 3 mm: a 30-frame window has forgotten the first ten.
TEST(DepthQuality, TemporalNoiseIsEachPixelsDeviationOverTheWindow) {
    QualityParams params;
    params.roi = {0, 0, 32, 24};
    params.flyingThresholdMeters = 1.0f;
    NoiseWindow window(params, 30);
    std::mt19937 random(5);
    for (int frame = 0; frame < 40; ++frame) {
        std::normal_distribution<float> noise(0.0f, frame < 10 ? 0.02f : 0.003f);
        frame::DepthData d = flat(32, 24, 0.0f);
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 32; ++x)
                d.depthMeters.at(x, y) = 2.0f + 0.01f * static_cast<float>(x) + noise(random);
        window.add(d, frame < 10 ? 100.0 : static_cast<double>(frame));
    }
    EXPECT_EQ(window.frames(), 30u);
    const auto temporal = window.temporalNoiseMm();
    ASSERT_TRUE(temporal.ok()) << temporal.error().message;
    EXPECT_NEAR(*temporal, 3.0, 0.15);
    const auto spatial = window.spatialNoiseMm();
    ASSERT_TRUE(spatial.ok());
    EXPECT_DOUBLE_EQ(*spatial, 24.5); // the median of 10 .. 39
}

// Two frames, pixel i at 1 m and 1 m + a_i: its deviation is a_i / sqrt(2). The a_i are a shuffled ramp
// (the middle two known exactly), plus one pixel 10 m apart and one tie with the middle, which crowd the
// middle ranks into few bins of the median's search. Both parities of the pixel count.
TEST(DepthQuality, TemporalNoiseIsTheExactMedianOfManyPixels) {
    for (const int width : {200, 199}) {
        QualityParams params;
        params.roi = {0, 0, width, 51};
        params.flyingThresholdMeters = 100.0f;
        const int n = width * 51;
        std::vector<float> offsets(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i)
            offsets[static_cast<std::size_t>(i)] = 1e-5f * static_cast<float>(i + 1);
        offsets[0] = 10.0f;
        offsets[1] = offsets[static_cast<std::size_t>(n / 2)];
        std::vector<float> sorted = offsets;
        std::sort(sorted.begin(), sorted.end());
        std::shuffle(offsets.begin(), offsets.end(), std::mt19937(3));
        NoiseWindow window(params, 2);
        frame::DepthData d = flat(width, 51, 1.0f);
        window.add(d, std::nullopt);
        for (int i = 0; i < n; ++i)
            d.depthMeters.pixels[static_cast<std::size_t>(i)] = 1.0f + offsets[static_cast<std::size_t>(i)];
        window.add(d, std::nullopt);
        std::vector<double> deviations;
        for (int i = 0; i < n; ++i) {
            const double a = static_cast<double>(d.depthMeters.pixels[static_cast<std::size_t>(i)]) - 1.0;
            deviations.push_back(std::abs(a) / std::sqrt(2.0) * 1000.0);
        }
        std::sort(deviations.begin(), deviations.end());
        const auto mid = static_cast<std::size_t>(n / 2);
        const double expected = n % 2 ? deviations[mid] : 0.5 * (deviations[mid - 1] + deviations[mid]);
        const auto temporal = window.temporalNoiseMm();
        ASSERT_TRUE(temporal.ok());
        EXPECT_NEAR(*temporal, expected, 1e-9) << n << " pixels";
    }
}

TEST(DepthQuality, TemporalNoiseNeedsAPixelValidInEveryFrame) {
    QualityParams params;
    params.roi = {0, 0, 4, 4};
    NoiseWindow window(params, 5);
    EXPECT_FALSE(window.temporalNoiseMm().ok());
    for (int frame = 0; frame < 5; ++frame) {
        frame::DepthData d = flat(4, 4, 1.0f);
        for (int i = 0; i < 16; ++i)
            d.depthMeters.pixels[static_cast<std::size_t>(i)] = i == frame ? 0.0f : 1.0f + 0.001f * frame;
        window.add(d, std::nullopt);
    }
    const auto temporal = window.temporalNoiseMm();
    ASSERT_TRUE(temporal.ok());
    EXPECT_NEAR(*temporal, 1.5811, 1e-3); // sample std of 0, 1, 2, 3, 4 mm
    EXPECT_FALSE(window.spatialNoiseMm().ok());
}

// Pixel centres on a polygon's edges decide by side, as a rasterizer's top-left rule does: on an edge with
// the polygon to its right or below, inside; to its left or above, outside.
TEST(DepthQuality, InsidePolygonHandCases) {
    const Polygon square{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    EXPECT_TRUE(insidePolygon(square, 2, 2));
    EXPECT_FALSE(insidePolygon(square, 5, 2));
    EXPECT_FALSE(insidePolygon(square, -1, 2));
    EXPECT_FALSE(insidePolygon(square, 2, -0.5));
    EXPECT_TRUE(insidePolygon(square, 0, 2)) << "left edge";
    EXPECT_FALSE(insidePolygon(square, 4, 2)) << "right edge";
    EXPECT_TRUE(insidePolygon(square, 2, 0)) << "top edge";
    EXPECT_FALSE(insidePolygon(square, 2, 4)) << "bottom edge";
    // An L: the notch (1..4, 1..4) is outside though it lies within the bounding box.
    const Polygon ell{{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
    EXPECT_TRUE(insidePolygon(ell, 0.5, 3.5));
    EXPECT_TRUE(insidePolygon(ell, 3.5, 0.5));
    EXPECT_TRUE(insidePolygon(ell, 0.5, 0.5));
    EXPECT_FALSE(insidePolygon(ell, 3, 3));
    EXPECT_FALSE(insidePolygon(ell, 1.5, 1.5));
    // A bow tie by the even-odd rule: each lobe inside, the crossing's sides outside.
    const Polygon bowTie{{0, 0}, {4, 4}, {4, 0}, {0, 4}};
    EXPECT_TRUE(insidePolygon(bowTie, 0.5, 2));
    EXPECT_TRUE(insidePolygon(bowTie, 3.5, 2));
    EXPECT_FALSE(insidePolygon(bowTie, 2, 0.5));
    EXPECT_FALSE(insidePolygon(Polygon{{0, 0}, {4, 4}}, 2, 2)) << "two vertices hold nothing";
    EXPECT_EQ(polygonBounds(ell), (Roi{0, 0, 4, 4}));
    EXPECT_EQ(polygonBounds(Polygon{{1.5, 2.25}, {7.0, 2.5}, {3.0, 9.75}}), (Roi{1, 2, 6, 8}));
}

// The right triangle (2, 2), (30, 2), (2, 20): a centre (x + 0.5, y + 0.5) is inside when x >= 2, y >= 2 and
// 18 (x - 1.5) + 28 (y - 1.5) < 504, i.e. 18 x + 28 y < 573 (an odd number, so no centre is on the slope).
const Polygon kTriangle{{2, 2}, {30, 2}, {2, 20}};
bool insideTriangle(int x, int y) {
    return x >= 2 && y >= 2 && 18 * x + 28 * y < 573;
}

QualityParams triangleParams() {
    QualityParams params;
    params.polygon = kTriangle;
    params.roi = polygonBounds(kTriangle);
    params.flyingThresholdMeters = 10.0f; // the step at the triangle's border is not what is tested
    return params;
}

// Inside: a noisy wall at 1 m with one hole; outside: a wall at 1.5 m with one hole too. The outside samples
// are in no count and no fit.
TEST(DepthQuality, APolygonRegionMeasuresOnlyTheSamplesWhoseCentresAreInside) {
    const frame::Intrinsics k = intrinsics(40, 30);
    frame::DepthData d = flat(40, 30, 1.5f);
    std::mt19937 random(7);
    std::normal_distribution<float> noise(0.0f, 0.002f);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            if (insideTriangle(x, y))
                d.depthMeters.at(x, y) = 1.0f + noise(random);
    d.depthMeters.at(3, 3) = 0.0f;   // inside
    d.depthMeters.at(28, 18) = 0.0f; // in the bounding box, outside
    const QualityParams params = triangleParams();
    ASSERT_EQ(params.roi, (Roi{2, 2, 28, 18}));
    const auto q = measureFrameQuality(d, k, params);
    ASSERT_TRUE(q.ok()) << q.error().message;
    std::size_t inside = 0;
    std::vector<Point3d> points;
    for (int y = params.roi.y; y < params.roi.y + params.roi.height; ++y) {
        for (int x = params.roi.x; x < params.roi.x + params.roi.width; ++x) {
            const std::size_t i =
                static_cast<std::size_t>(y - params.roi.y) * params.roi.width + (x - params.roi.x);
            if (!insideTriangle(x, y)) {
                EXPECT_EQ(q->causes[i], SampleCause::OutsideRegion) << x << "," << y;
                continue;
            }
            ++inside;
            EXPECT_NE(q->causes[i], SampleCause::OutsideRegion) << x << "," << y;
            const double z = d.depthMeters.at(x, y);
            if (z > 0.0)
                points.push_back({(x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z});
        }
    }
    EXPECT_EQ(q->fill.roiSamples, inside);
    EXPECT_EQ(q->fill.valid, inside - 1);
    EXPECT_EQ(q->fill.noMeasurement, 1u);
    EXPECT_DOUBLE_EQ(q->fill.fillRate(), static_cast<double>(inside - 1) / static_cast<double>(inside));
    ASSERT_TRUE(q->plane) << q->planeError;
    const auto robust = fitPlaneRobust(points, params.fit);
    const auto dqt = dqtPlaneFitRms(points);
    ASSERT_TRUE(robust.ok() && dqt.ok());
    EXPECT_NEAR(q->plane->planeFitRmsMm, robust->rmsMeters * 1000.0, 1e-9);
    EXPECT_NEAR(q->plane->dqtPlaneFitRmsMm, *dqt * 1000.0, 1e-9);
    EXPECT_NEAR(q->plane->distanceMm, 1000.0, 1.0);
    // The overlay: the hole inside in its cause's colour, everything outside (the hole there too)
    // transparent.
    const RgbaImage overlay = causeOverlay(q->causes, params.roi.width, params.roi.height);
    ASSERT_EQ(overlay.pixels.size(), q->causes.size() * 4);
    for (std::size_t i = 0; i < q->causes.size(); ++i) {
        const bool missingInside = q->causes[i] == SampleCause::NoMeasurement;
        EXPECT_EQ(overlay.pixels[i * 4 + 3], missingInside ? 255 : 0) << i;
    }
    EXPECT_EQ(overlay.pixels[(1u * 28u + 1u) * 4u + 3u], 255) << "the hole at (3, 3)";
}

// Inside, each pixel alternates 1 m and 1.002 m (1.414 mm deviation); outside, 1 m and 1.1 m. The window
// counts only the inside: its median is the inside's deviation, and its maps are NaN outside.
TEST(DepthQuality, ANoiseWindowOverAPolygonKeepsOnlyTheInside) {
    const QualityParams params = triangleParams();
    NoiseWindow window(params, 4);
    for (int frame = 0; frame < 4; ++frame) {
        frame::DepthData d = flat(40, 30, frame % 2 ? 1.1f : 1.0f);
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x)
                if (insideTriangle(x, y))
                    d.depthMeters.at(x, y) = frame % 2 ? 1.002f : 1.0f;
        window.add(d, std::nullopt);
    }
    const auto temporal = window.temporalNoiseMm();
    ASSERT_TRUE(temporal.ok()) << temporal.error().message;
    EXPECT_NEAR(*temporal, 2.0 / std::sqrt(3.0), 1e-3); // sample std of 0, 2, 0, 2 mm
    const frame::Plane<float> fill = window.fillMapPercent();
    const frame::Plane<float> deviation = window.temporalStdMapMm();
    ASSERT_EQ(fill.width, 28);
    ASSERT_EQ(fill.height, 18);
    for (int y = 0; y < 18; ++y) {
        for (int x = 0; x < 28; ++x) {
            if (insideTriangle(x + 2, y + 2)) {
                EXPECT_EQ(fill.at(x, y), 100.0f) << x << "," << y;
                EXPECT_NEAR(deviation.at(x, y), 2.0 / std::sqrt(3.0), 1e-3) << x << "," << y;
            } else {
                EXPECT_TRUE(std::isnan(fill.at(x, y))) << x << "," << y;
                EXPECT_TRUE(std::isnan(deviation.at(x, y))) << x << "," << y;
            }
        }
    }
}

} // namespace
} // namespace dc::processing
