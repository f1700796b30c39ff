#include "processing/confidence_estimator.h"

#include "processing/parallel.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace dc::processing {

namespace {

using frame::Confidence;

// Mirrored index (the image edge is not a hole): -1 -> 1, size -> size - 2.
int mirror(int i, int size) {
    if (size == 1)
        return 0;
    return i < 0 ? -i : (i >= size ? 2 * size - 2 - i : i);
}

// Horizontal 3-sums of one row: measured count, depth and squared depth (unmeasured pixels add nothing).
// Double, because the variance below is taken as E[d^2] - E[d]^2 around the centre.
struct RowSums {
    std::vector<double> count, sum, squares;
};

void horizontalSums(const float* row, int w, std::vector<double>& scratch, RowSums& out) {
    scratch.resize(3 * static_cast<std::size_t>(w));
    double* c = scratch.data();
    double* s = c + w;
    double* q = s + w;
    for (int x = 0; x < w; ++x) {
        const bool m = frame::isMeasured(row[x]);
        c[x] = m ? 1.0 : 0.0;
        s[x] = m ? row[x] : 0.0;
        q[x] = s[x] * s[x];
    }
    out.count.resize(static_cast<std::size_t>(w));
    out.sum.resize(static_cast<std::size_t>(w));
    out.squares.resize(static_cast<std::size_t>(w));
    for (const auto& [in, dst] :
         {std::pair{c, out.count.data()}, {s, out.sum.data()}, {q, out.squares.data()}}) {
        for (int x = 1; x + 1 < w; ++x)
            dst[x] = in[x - 1] + in[x] + in[x + 1];
        dst[0] = in[mirror(-1, w)] + in[0] + in[mirror(1, w)];
        dst[w - 1] = in[mirror(w - 2, w)] + in[w - 1] + in[mirror(w, w)];
    }
}

// Levels of one row from the 3x3 sums (three rows of horizontal sums). The limits are compared squared and
// scaled by n, so that a pixel costs no square root or division: spread / centre <= s is
// n * squares - sum^2 <= (n * s * centre)^2, and change / centre <= c is |change| <= c * centre.
void classifyRow(const float* depth, const float* before, const RowSums* const rows[3], int w,
                 const ConfidenceEstimatorParams& params, std::uint8_t* levels) {
    for (int x = 0; x < w; ++x) {
        const double centre = depth[x];
        if (!frame::isMeasured(depth[x]))
            continue;
        const double n = rows[0]->count[x] + rows[1]->count[x] + rows[2]->count[x]; // >= 1: the pixel itself
        const double sum = rows[0]->sum[x] + rows[1]->sum[x] + rows[2]->sum[x];
        const double squares = rows[0]->squares[x] + rows[1]->squares[x] + rows[2]->squares[x];
        const double scatter = std::max(0.0, n * squares - sum * sum); // n^2 times the variance
        const int invalid = 9 - static_cast<int>(n + 0.5);
        // Unknown on a first frame or where the previous one had no measurement: then it does not count.
        const double change = before && frame::isMeasured(before[x]) ? std::abs(centre - before[x]) : 0.0;
        const auto within = [&](int maxInvalid, float maxSpread, float maxChange) {
            const double limit = n * maxSpread * centre;
            return invalid <= maxInvalid && scatter <= limit * limit && change <= maxChange * centre;
        };
        const Confidence c =
            within(params.highInvalidNeighbours, params.highSpread, params.highChange) ? Confidence::High
            : within(params.mediumInvalidNeighbours, params.mediumSpread, params.mediumChange)
                ? Confidence::Medium
                : Confidence::Low;
        levels[x] = static_cast<std::uint8_t>(c);
    }
}

// Levels of rows [begin, end); each band keeps its own ring of horizontal sums, so bands run in parallel.
void estimateRows(const frame::Plane<float>& depth, const frame::Plane<float>* previous,
                  const ConfidenceEstimatorParams& params, int begin, int end,
                  frame::Plane<std::uint8_t>& out) {
    const int w = depth.width;
    const auto rowOf = [&](const frame::Plane<float>& plane, int y) {
        return &plane.pixels[static_cast<std::size_t>(y) * w];
    };
    // Horizontal sums of three consecutive rows at a time: row i lives in slot i % 3.
    RowSums slots[3];
    int slotRow[3] = {-1, -1, -1};
    std::vector<double> scratch;
    const auto sumsOf = [&](int y) -> const RowSums* {
        RowSums& slot = slots[y % 3];
        if (slotRow[y % 3] != y) {
            horizontalSums(rowOf(depth, y), w, scratch, slot);
            slotRow[y % 3] = y;
        }
        return &slot;
    };
    for (int y = begin; y < end; ++y) {
        const RowSums* rows[3] = {sumsOf(mirror(y - 1, depth.height)), sumsOf(y),
                                  sumsOf(mirror(y + 1, depth.height))};
        classifyRow(rowOf(depth, y), previous ? rowOf(*previous, y) : nullptr, rows, w, params,
                    &out.pixels[static_cast<std::size_t>(y) * w]);
    }
}

} // namespace

frame::Plane<std::uint8_t> estimateConfidence(const frame::Plane<float>& depth,
                                              const frame::Plane<float>* previous,
                                              const ConfidenceEstimatorParams& params) {
    frame::Plane<std::uint8_t> out(depth.width, depth.height, static_cast<std::uint8_t>(Confidence::Low));
    if (depth.empty())
        return out;
    const bool temporal = previous && previous->width == depth.width && previous->height == depth.height;
    constexpr int kMinRowsPerBand = 32;
    parallelRanges(depth.height, kMinRowsPerBand, [&](int begin, int end) {
        estimateRows(depth, temporal ? previous : nullptr, params, begin, end, out);
    });
    return out;
}

bool ConfidenceEstimatorStage::wanted(const ProcessingSettings&, const Needs& needs) const {
    return needs.confidence;
}

frame::FramePtr ConfidenceEstimatorStage::process(frame::FramePtr frame, const ProcessingSettings&) {
    if (!frame || !frame->sceneDepth || !frame->sceneDepth->confidence.empty() ||
        frame->sceneDepth->depthMeters.empty())
        return frame;
    if (!current_ || current_->timestampNs != frame->timestampNs) {
        previous_ = std::move(current_);
        current_ = frame;
    }
    auto estimated = std::make_shared<frame::Frame>(*frame);
    frame::DepthData& depth = *estimated->sceneDepth;
    const frame::Plane<float>* previous = previous_ ? &previous_->sceneDepth->depthMeters : nullptr;
    depth.confidence = estimateConfidence(depth.depthMeters, previous, params_);
    depth.confidenceEstimated = true;
    return estimated;
}

} // namespace dc::processing
