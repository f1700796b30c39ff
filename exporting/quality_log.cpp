#include "exporting/quality_log.h"

#include "base/files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <utility>

namespace dc::exporting {

namespace {

using nlohmann::json;

json optionalJson(const std::optional<double>& value) {
    return value ? json(*value) : json(nullptr);
}

// One row's figures under the keys `depthcloud quality --json` uses; null where not measured.
json rowJson(const QualityLog::Row& r) {
    json j{{"frame", r.frame},
           {"timestampNs", r.timestampNs},
           {"roi", {r.roi.x, r.roi.y, r.roi.width, r.roi.height}},
           {"temporalNoiseMm", optionalJson(r.temporalNoiseMm)},
           {"spatialNoiseMm", optionalJson(r.spatialNoiseMm)},
           {"noiseWindowFrames", r.windowFilled},
           {"alignmentPx", r.alignment ? json(r.alignment->medianPx) : json(nullptr)},
           {"alignmentMm", r.alignment ? json(r.alignment->medianMm) : json(nullptr)}};
    j["roiPolygon"] = r.polygon ? json(*r.polygon) : json(nullptr);
    for (const char* key :
         {"fillRate", "distanceMm", "angleDeg", "planeFitRmsMm", "planeFitRmsPercent", "inlierFraction",
          "dqtPlaneFitRmsMm", "zAccuracyPercent", "subpixelRms", "expectedNoiseMm"})
        j[key] = nullptr;
    if (const auto& f = r.fill) {
        j["fillRate"] = f->fillRate();
        j["shortfall"] = {{"noMeasurement", f->fraction(f->noMeasurement)},
                          {"outOfRange", f->fraction(f->outOfRange)},
                          {"lowConfidence", f->fraction(f->lowConfidence)},
                          {"flyingPixel", f->fraction(f->flyingPixel)}};
    }
    if (const auto& p = r.plane) {
        j["distanceMm"] = p->distanceMm;
        j["angleDeg"] = p->angleDeg;
        j["planeFitRmsMm"] = p->planeFitRmsMm;
        j["planeFitRmsPercent"] = p->planeFitRmsPercent;
        j["inlierFraction"] = p->inlierFraction;
        j["dqtPlaneFitRmsMm"] = p->dqtPlaneFitRmsMm;
        j["zAccuracyPercent"] = optionalJson(p->zAccuracyPercent);
        j["subpixelRms"] = optionalJson(p->subpixelRms);
        j["expectedNoiseMm"] = optionalJson(p->expectedNoiseMm);
    }
    return j;
}

constexpr const char* kCsvHeader =
    "frame,timestamp_ns,roi_x,roi_y,roi_width,roi_height,fill_rate,no_measurement,out_of_range,"
    "low_confidence,flying_pixel,distance_mm,angle_deg,plane_fit_rms_mm,plane_fit_rms_percent,"
    "inlier_fraction,dqt_plane_fit_rms_mm,z_accuracy_percent,subpixel_rms,expected_noise_mm,temporal_noise_"
    "mm,"
    "spatial_noise_mm,noise_window_frames,alignment_px,alignment_mm,roi_polygon\n";

// A figure as a CSV cell: round-trip precision, empty where not measured.
std::string cell(const std::optional<double>& value) {
    if (!value)
        return ",";
    char text[40];
    std::snprintf(text, sizeof text, ",%.17g", *value);
    return text;
}

// A lasso as one quoted CSV cell in `quality --roi-polygon`'s syntax ("x,y;x,y;..."), so a saved region can
// be measured again headless; empty for a rectangle.
std::string polygonCell(const std::shared_ptr<const processing::Polygon>& polygon) {
    if (!polygon)
        return {};
    std::string text;
    for (const auto& [x, y] : *polygon) {
        char vertex[64];
        std::snprintf(vertex, sizeof vertex, "%s%.17g,%.17g", text.empty() ? "" : ";", x, y);
        text += vertex;
    }
    return '"' + text + '"';
}

std::string csvLine(const QualityLog::Row& r) {
    std::string line = std::to_string(r.frame) + "," + std::to_string(r.timestampNs) + "," +
                       std::to_string(r.roi.x) + "," + std::to_string(r.roi.y) + "," +
                       std::to_string(r.roi.width) + "," + std::to_string(r.roi.height);
    const auto& f = r.fill;
    const auto fraction = [&](std::size_t processing::FillBreakdown::*count) -> std::optional<double> {
        return f ? std::optional(f->fraction((*f).*count)) : std::nullopt;
    };
    line += cell(f ? std::optional(f->fillRate()) : std::nullopt);
    for (auto count : {&processing::FillBreakdown::noMeasurement, &processing::FillBreakdown::outOfRange,
                       &processing::FillBreakdown::lowConfidence, &processing::FillBreakdown::flyingPixel})
        line += cell(fraction(count));
    const auto& p = r.plane;
    const auto figure = [&](double processing::PlaneFigures::*value) -> std::optional<double> {
        return p ? std::optional((*p).*value) : std::nullopt;
    };
    for (auto value :
         {&processing::PlaneFigures::distanceMm, &processing::PlaneFigures::angleDeg,
          &processing::PlaneFigures::planeFitRmsMm, &processing::PlaneFigures::planeFitRmsPercent,
          &processing::PlaneFigures::inlierFraction, &processing::PlaneFigures::dqtPlaneFitRmsMm})
        line += cell(figure(value));
    line += cell(p ? p->zAccuracyPercent : std::nullopt);
    line += cell(p ? p->subpixelRms : std::nullopt);
    line += cell(p ? p->expectedNoiseMm : std::nullopt);
    line += cell(r.temporalNoiseMm) + cell(r.spatialNoiseMm) + "," + std::to_string(r.windowFilled);
    const auto& a = r.alignment;
    line += cell(a ? std::optional(a->medianPx) : std::nullopt) +
            cell(a ? std::optional(a->medianMm) : std::nullopt) + "," + polygonCell(r.polygon) + "\n";
    return line;
}

} // namespace

bool QualityLog::add(const std::shared_ptr<const processing::ShownQuality>& quality,
                     std::int64_t timestampNs) {
    if (!quality || quality == last_)
        return false;
    last_ = quality;
    std::shared_ptr<const processing::Polygon> polygon;
    if (!quality->polygon.empty())
        polygon = !rows_.empty() && rows_.back().polygon && *rows_.back().polygon == quality->polygon
                      ? rows_.back().polygon
                      : std::make_shared<const processing::Polygon>(quality->polygon);
    Row row{quality->sequence,
            timestampNs,
            quality->roi,
            std::move(polygon),
            std::nullopt,
            std::nullopt,
            quality->temporalNoiseMm,
            quality->spatialNoiseMm,
            quality->windowFilled,
            quality->alignment};
    if (quality->figures) {
        row.fill = quality->figures->fill;
        row.plane = quality->figures->plane;
    }
    if (rows_.size() == kMaxRows) {
        rows_.pop_front();
        ++dropped_;
    }
    rows_.push_back(std::move(row));
    return true;
}

void QualityLog::clear() {
    rows_.clear();
    dropped_ = 0;
}

const char* toString(QualityFigure figure) {
    switch (figure) {
    case QualityFigure::FillRate:
        return "fill rate %";
    case QualityFigure::PlaneFitRmsMm:
        return "plane-fit RMS mm";
    case QualityFigure::DistanceMm:
        return "distance mm";
    case QualityFigure::TemporalNoiseMm:
        return "temporal noise mm";
    }
    return "";
}

std::vector<double> qualitySeries(const QualityLog& log, QualityFigure figure) {
    std::vector<double> series;
    for (const QualityLog::Row& r : log.rows()) {
        std::optional<double> value;
        switch (figure) {
        case QualityFigure::FillRate:
            value = r.fill ? std::optional(100.0 * r.fill->fillRate()) : std::nullopt;
            break;
        case QualityFigure::PlaneFitRmsMm:
            value = r.plane ? std::optional(r.plane->planeFitRmsMm) : std::nullopt;
            break;
        case QualityFigure::DistanceMm:
            value = r.plane ? std::optional(r.plane->distanceMm) : std::nullopt;
            break;
        case QualityFigure::TemporalNoiseMm:
            value = r.temporalNoiseMm;
            break;
        }
        if (value)
            series.push_back(*value);
    }
    return series;
}

namespace {

struct DistanceBin {
    std::vector<double> distances, rms, expected;
};

} // namespace

std::vector<NoiseAtDistance> noiseOverDistance(const QualityLog& log, int bins) {
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = -nearest;
    for (const QualityLog::Row& r : log.rows()) {
        if (r.plane) {
            nearest = std::min(nearest, r.plane->distanceMm);
            farthest = std::max(farthest, r.plane->distanceMm);
        }
    }
    if (!(nearest <= farthest) || bins < 1)
        return {};
    const double step = (farthest - nearest) / bins;
    std::vector<DistanceBin> binned(static_cast<std::size_t>(bins));
    for (const QualityLog::Row& r : log.rows()) {
        if (!r.plane)
            continue;
        const auto at = step > 0.0 ? static_cast<std::size_t>((r.plane->distanceMm - nearest) / step) : 0;
        DistanceBin& b = binned[std::min(at, binned.size() - 1)];
        b.distances.push_back(r.plane->distanceMm);
        b.rms.push_back(r.plane->planeFitRmsMm);
        if (r.plane->expectedNoiseMm)
            b.expected.push_back(*r.plane->expectedNoiseMm);
    }
    std::vector<NoiseAtDistance> out;
    for (const DistanceBin& b : binned) {
        if (b.distances.empty())
            continue;
        NoiseAtDistance n{processing::medianOf(b.distances), processing::medianOf(b.rms), std::nullopt,
                          b.distances.size()};
        if (!b.expected.empty())
            n.expectedNoiseMm = processing::medianOf(b.expected);
        out.push_back(n);
    }
    return out;
}

std::string qualityCsv(const QualityLog& log) {
    std::string text = kCsvHeader;
    for (const QualityLog::Row& r : log.rows())
        text += csvLine(r);
    return text;
}

std::string qualityJson(const QualityLog& log, const std::string& source, const std::string& settingsJson) {
    json rows = json::array();
    for (const QualityLog::Row& r : log.rows())
        rows.push_back(rowJson(r));
    const bool empty = log.rows().empty();
    json j{{"source", source},
           {"firstFrame", empty ? json(nullptr) : json(log.rows().front().frame)},
           {"lastFrame", empty ? json(nullptr) : json(log.rows().back().frame)},
           {"rows", log.rows().size()},
           {"rowsDroppedForNewer", log.dropped()},
           {"settings", json::parse(settingsJson, nullptr, false)},
           {"frames", std::move(rows)}};
    return j.dump(2) + "\n";
}

Expected<std::string> writeQualityLog(const std::string& parent, const QualityLog& log,
                                      const std::string& source, const std::string& settingsJson) {
    if (log.rows().empty())
        return Error{"no quality figures to save yet (show the Quality panel while frames arrive)"};
    auto dir = base::createFreshDirectory(parent, "quality-" + std::to_string(log.rows().front().frame) +
                                                      "-" + std::to_string(log.rows().back().frame));
    if (!dir)
        return dir.error();
    if (Status s = base::writeTextFile(*dir + "/figures.csv", qualityCsv(log)); !s)
        return s.error();
    if (Status s = base::writeTextFile(*dir + "/figures.json", qualityJson(log, source, settingsJson)); !s)
        return s.error();
    return dir;
}

} // namespace dc::exporting
