#pragma once

#include "base/expected.h"
#include "processing/shown_frame.h"

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::exporting {

// The Quality panel's figures of every frame it showed, in order, for "Save figures": one row per frame
// (the panel measures a paused frame again when its region changes: that is a new row too), without the
// per-sample causes. Bounded: past kMaxRows the oldest rows go, and the saved range says which remain.
class QualityLog {
public:
    static constexpr std::size_t kMaxRows = 108000; // an hour at 30 fps

    struct Row {
        std::uint64_t frame = 0;
        std::int64_t timestampNs = 0;
        processing::Roi roi; // a polygon's bounds when there is one
        // The lasso's vertices; null for a rectangle. Rows share one while it stays the same: a log of
        // an hour would otherwise hold an hour of copies.
        std::shared_ptr<const processing::Polygon> polygon;
        std::optional<processing::FillBreakdown> fill; // unset: the frame could not be measured
        std::optional<processing::PlaneFigures> plane;
        std::optional<double> temporalNoiseMm;
        std::optional<double> spatialNoiseMm;
        std::size_t windowFilled = 0;
        std::optional<processing::EdgeAlignment> alignment;
    };

    // Adds the figures unless they are the very ones added last (the panel draws them every UI frame).
    // Returns whether a row was added.
    bool add(const std::shared_ptr<const processing::ShownQuality>& quality, std::int64_t timestampNs);
    // Forgets every row; the figures added last stay known, so they are not added again.
    void clear();
    const std::deque<Row>& rows() const { return rows_; }
    std::size_t dropped() const { return dropped_; } // rows that made way for newer ones

private:
    std::deque<Row> rows_;
    std::shared_ptr<const processing::ShownQuality> last_; // held, so no later figures share its address
    std::size_t dropped_ = 0;
};

// The figures a Quality panel plots over time.
enum class QualityFigure { FillRate, PlaneFitRmsMm, DistanceMm, TemporalNoiseMm };
inline constexpr QualityFigure kQualityFigures[] = {QualityFigure::FillRate, QualityFigure::PlaneFitRmsMm,
                                                    QualityFigure::DistanceMm,
                                                    QualityFigure::TemporalNoiseMm};
const char* toString(QualityFigure figure); // "fill rate %", "plane-fit RMS mm", ...
// One figure of every row that measured it, oldest first (the fill rate as a percentage).
std::vector<double> qualitySeries(const QualityLog& log, QualityFigure figure);

// The plane-fit RMS against distance, the figure that tells a camera at its design noise from one with a
// calibration fault: the rows with a plane fit in `bins` equal steps of distance between the nearest and the
// farthest, each non-empty step's median distance, median RMS and median expected noise (where the rows had
// one), nearest first. One step when every row is at the same distance.
struct NoiseAtDistance {
    double distanceMm = 0.0;
    double planeFitRmsMm = 0.0;
    std::optional<double> expectedNoiseMm;
    std::size_t frames = 0;
};
std::vector<NoiseAtDistance> noiseOverDistance(const QualityLog& log, int bins);

// Every row as CSV: a header, then one line per frame; an unmeasured figure is an empty cell.
std::string qualityCsv(const QualityLog& log);
// The rows as JSON with what they were measured on: the source, the settings (the JSON the window saves),
// the frame range; each row's keys are those of `depthcloud quality --json`.
std::string qualityJson(const QualityLog& log, const std::string& source, const std::string& settingsJson);

// Writes figures.csv and figures.json into a new directory under `parent` (quality-FIRST-LAST, numbered
// when taken); returns the directory. An empty log is an error, and nothing is written.
Expected<std::string> writeQualityLog(const std::string& parent, const QualityLog& log,
                                      const std::string& source, const std::string& settingsJson);

} // namespace dc::exporting
