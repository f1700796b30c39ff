// The Quality panel's kept figures (exporting/quality_log.h): one row per new set of figures, the plotted
// series, CSV cells for unmeasured figures, and the bound on kept rows.

#include "exporting/quality_log.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>

namespace dc::exporting {
namespace {

std::shared_ptr<const processing::ShownQuality> figures(std::uint64_t frame, double rmsMm,
                                                        bool plane = true) {
    auto q = std::make_shared<processing::ShownQuality>();
    q->sequence = frame;
    q->roi = {1, 2, 30, 40};
    processing::FrameQuality f;
    f.fill.roiSamples = 1200;
    f.fill.valid = 1200 - frame;
    f.fill.noMeasurement = frame;
    if (plane) {
        f.plane = processing::PlaneFigures{};
        f.plane->planeFitRmsMm = rmsMm;
        f.plane->distanceMm = 1000.0 + static_cast<double>(frame);
    } else {
        f.planeError = "too few samples";
    }
    q->figures = std::move(f);
    return q;
}

TEST(QualityLog, EachNewSetOfFiguresIsOneRowAndTheSameSetIsNotAddedTwice) {
    QualityLog log;
    const auto a = figures(7, 1.5);
    EXPECT_TRUE(log.add(a, 100));
    EXPECT_FALSE(log.add(a, 100)) << "the panel draws the same figures every UI frame";
    EXPECT_TRUE(log.add(figures(7, 1.25), 100)) << "a paused frame measured again over another region";
    EXPECT_FALSE(log.add(nullptr, 0));
    ASSERT_EQ(log.rows().size(), 2u);
    EXPECT_EQ(log.rows()[0].frame, 7u);
    EXPECT_EQ(log.rows()[1].plane->planeFitRmsMm, 1.25);

    const auto shownWhenCleared = figures(8, 2.0);
    EXPECT_TRUE(log.add(shownWhenCleared, 200));
    log.clear();
    EXPECT_TRUE(log.rows().empty());
    EXPECT_FALSE(log.add(shownWhenCleared, 200)) << "Clear forgets what was shown, it does not re-add it";
    EXPECT_TRUE(log.add(figures(9, 2.5), 300));
    EXPECT_EQ(log.rows().size(), 1u);
}

TEST(QualityLog, TheSeriesHoldsTheFramesThatMeasuredTheFigure) {
    QualityLog log;
    log.add(figures(1, 1.0), 0);
    log.add(figures(2, 0.0, false), 0); // no plane fit: no RMS, a fill rate all the same
    log.add(figures(3, 3.0), 0);
    EXPECT_EQ(qualitySeries(log, QualityFigure::PlaneFitRmsMm), (std::vector<double>{1.0, 3.0}));
    EXPECT_EQ(qualitySeries(log, QualityFigure::DistanceMm), (std::vector<double>{1001.0, 1003.0}));
    const std::vector<double> fill = qualitySeries(log, QualityFigure::FillRate);
    ASSERT_EQ(fill.size(), 3u);
    EXPECT_DOUBLE_EQ(fill[1], 100.0 * 1198.0 / 1200.0);
    EXPECT_TRUE(qualitySeries(log, QualityFigure::TemporalNoiseMm).empty());
}

// Frames at 1.0 .. 2.0 m whose RMS follows the stereo model (z^2 scaled), with its expected noise half of it:
// each distance step holds the rows within it, its medians are those rows' medians, and a row without a
// plane fit is left out.
TEST(QualityLog, NoiseOverDistanceIsEachDistanceStepsMedians) {
    QualityLog log;
    const auto at = [](std::uint64_t frame, double distanceMm, bool plane = true) {
        auto q = std::const_pointer_cast<processing::ShownQuality>(figures(frame, 0.0, plane));
        if (plane) {
            q->figures->plane->distanceMm = distanceMm;
            q->figures->plane->planeFitRmsMm = distanceMm * distanceMm * 1e-6;
            q->figures->plane->expectedNoiseMm = 0.5 * distanceMm * distanceMm * 1e-6;
        }
        return std::shared_ptr<const processing::ShownQuality>(q);
    };
    std::uint64_t frame = 0;
    for (double d : {1000.0, 1010.0, 1020.0, 1990.0, 2000.0, 1500.0})
        log.add(at(++frame, d), 0);
    log.add(at(++frame, 0.0, false), 0);
    const std::vector<NoiseAtDistance> bins = noiseOverDistance(log, 4);
    ASSERT_EQ(bins.size(), 3u) << "1.0-1.25 m, 1.5-1.75 m and 1.75-2.0 m; 1.25-1.5 m is empty";
    EXPECT_DOUBLE_EQ(bins[0].distanceMm, 1010.0);
    EXPECT_EQ(bins[0].frames, 3u);
    EXPECT_DOUBLE_EQ(bins[0].planeFitRmsMm, 1010.0 * 1010.0 * 1e-6);
    EXPECT_DOUBLE_EQ(*bins[0].expectedNoiseMm, 0.5 * 1010.0 * 1010.0 * 1e-6);
    EXPECT_DOUBLE_EQ(bins[1].distanceMm, 1500.0);
    EXPECT_DOUBLE_EQ(bins[2].distanceMm, 1995.0) << "the farthest row is in the last step";
    EXPECT_DOUBLE_EQ(bins[2].planeFitRmsMm, 0.5 * (1990.0 * 1990.0 + 2000.0 * 2000.0) * 1e-6);

    QualityLog still;
    still.add(figures(1, 1.0), 0);
    still.add(figures(1, 3.0), 0);
    const auto one = noiseOverDistance(still, 8);
    ASSERT_EQ(one.size(), 1u) << "one distance, one step";
    EXPECT_DOUBLE_EQ(one[0].planeFitRmsMm, 2.0);
    EXPECT_FALSE(one[0].expectedNoiseMm) << "no baseline, no expected noise";
    EXPECT_TRUE(noiseOverDistance(QualityLog{}, 8).empty());
}

// The colour alignment travels with its frame into the CSV's alignment columns and the JSON's keys, and
// stays empty (null) for a frame that did not measure it.
TEST(QualityLog, TheColourAlignmentIsSavedWhereMeasured) {
    QualityLog log;
    auto aligned = std::const_pointer_cast<processing::ShownQuality>(figures(1, 1.0));
    aligned->alignment = processing::EdgeAlignment{0.75, 0.8, 3.25, 100, 90};
    log.add(aligned, 0);
    log.add(figures(2, 1.0), 0);
    std::istringstream csv(qualityCsv(log));
    std::string header, first, second;
    std::getline(csv, header);
    std::getline(csv, first);
    std::getline(csv, second);
    EXPECT_TRUE(header.ends_with(",alignment_px,alignment_mm,roi_polygon"));
    EXPECT_TRUE(first.ends_with(",0.75,3.25,")) << first;
    EXPECT_TRUE(second.ends_with(",,,")) << second;
    const auto j = nlohmann::json::parse(qualityJson(log, "synthetic", "{}"));
    EXPECT_EQ(j["frames"][0]["alignmentPx"], 0.75);
    EXPECT_EQ(j["frames"][0]["alignmentMm"], 3.25);
    EXPECT_TRUE(j["frames"][1]["alignmentPx"].is_null());
}

// A lasso's region is saved as its vertices beside its bounds (which alone would claim samples the figures
// never counted); rows measured with the same lasso share one copy of it.
TEST(QualityLog, ALassosVerticesAreSavedWithEachRowMeasuredInside) {
    const processing::Polygon lasso{{1.5, 2.0}, {31.0, 2.25}, {16.0, 42.0}};
    QualityLog log;
    for (std::uint64_t frame : {1u, 2u}) {
        auto inside = std::const_pointer_cast<processing::ShownQuality>(figures(frame, 1.0));
        inside->polygon = lasso;
        log.add(inside, 0);
    }
    log.add(figures(3, 1.0), 0);
    ASSERT_EQ(log.rows().size(), 3u);
    ASSERT_TRUE(log.rows()[0].polygon);
    EXPECT_EQ(*log.rows()[0].polygon, lasso);
    EXPECT_EQ(log.rows()[0].polygon, log.rows()[1].polygon) << "one copy while the lasso stays";
    EXPECT_FALSE(log.rows()[2].polygon);
    std::istringstream csv(qualityCsv(log));
    std::string header, first, second, third;
    std::getline(csv, header);
    std::getline(csv, first);
    std::getline(csv, second);
    std::getline(csv, third);
    EXPECT_TRUE(first.ends_with(",\"1.5,2;31,2.25;16,42\""))
        << "as quality --roi-polygon takes it: " << first;
    EXPECT_TRUE(third.ends_with(",")) << third;
    const auto j = nlohmann::json::parse(qualityJson(log, "synthetic", "{}"));
    EXPECT_EQ(j["frames"][0]["roiPolygon"], nlohmann::json(lasso));
    EXPECT_TRUE(j["frames"][2]["roiPolygon"].is_null());
}

TEST(QualityLog, CsvLeavesUnmeasuredFiguresEmptyAndRoundTripsTheRest) {
    QualityLog log;
    log.add(figures(4, 0.1), 123456789);
    log.add(figures(5, 0.0, false), 123456790);
    std::stringstream csv(qualityCsv(log));
    std::string header, first, second;
    std::getline(csv, header);
    std::getline(csv, first);
    std::getline(csv, second);
    const auto columns = [](const std::string& line) {
        return std::count(line.begin(), line.end(), ',') + 1;
    };
    EXPECT_EQ(columns(first), columns(header));
    EXPECT_EQ(columns(second), columns(header));
    EXPECT_EQ(first.rfind("4,123456789,1,2,30,40,", 0), 0u) << first;
    EXPECT_NE(first.find(",0.10000000000000001,"), std::string::npos) << "the RMS to the last bit: " << first;
    EXPECT_NE(second.find(",,,,,,,,"), std::string::npos) << "no plane, no noise: empty cells: " << second;
}

TEST(QualityLog, PastItsBoundTheOldestRowsMakeWayAndAreCounted) {
    QualityLog log;
    for (std::uint64_t i = 0; i < QualityLog::kMaxRows + 3; ++i)
        log.add(figures(i, 1.0), 0);
    EXPECT_EQ(log.rows().size(), QualityLog::kMaxRows);
    EXPECT_EQ(log.dropped(), 3u);
    EXPECT_EQ(log.rows().front().frame, 3u);
}

} // namespace
} // namespace dc::exporting
