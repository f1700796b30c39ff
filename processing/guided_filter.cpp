#include "processing/guided_filter.h"

#include "processing/parallel.h"
#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

namespace dc::processing {

namespace {

using frame::Plane;

// Interpolated weights below this carry no usable measurement (a hole's neighbour far from any sample).
constexpr float kMinWeight = 1e-3f;
// A window whose fit is hopeless still counts a little, so a node with data never ends up without a model.
constexpr float kMinFitWeight = 1e-30f;
constexpr int kRowsPerPiece = 16;
// frame::isMeasured() as two comparisons, which vectorise (isfinite does not): NaN fails both.
constexpr float kFarthest = std::numeric_limits<float>::max();

// Sums of K per-pixel quantities over every window [x-r, x+r] x [y-r, y+r] clipped to the w x h image,
// for rows [y0, y1). Column sums slide down and a row sum slides across, both in double: a window costs
// O(1) whatever the radius, and each sum keeps ~1e-16 relative precision over its (2r+1)^2 terms, where
// float running sums or a summed-area table over a whole 8K image lose the digits variances need.
template <int K, class Quantities, class Emit>
void windowSums(int w, int h, int r, int y0, int y1, const Quantities& quantities, const Emit& emit) {
    using Sums = std::array<double, K>;
    std::vector<Sums> columns(static_cast<std::size_t>(w), Sums{});
    // Each row's quantities enter the column sums once and leave them 2r + 1 rows later: keep them in a
    // ring of rows rather than computing them twice.
    const int ringRows = std::min(2 * r + 2, h + 1);
    std::vector<Sums> ring(static_cast<std::size_t>(ringRows) * w);
    const auto ringRow = [&](int y) { return ring.data() + static_cast<std::size_t>(y % ringRows) * w; };
    const auto addRow = [&](int y) {
        Sums* cached = ringRow(y);
        for (int x = 0; x < w; ++x) {
            cached[x] = quantities(x, y);
            for (int k = 0; k < K; ++k)
                columns[x][k] += cached[x][k];
        }
    };
    const auto removeRow = [&](int y) {
        const Sums* cached = ringRow(y);
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < K; ++k)
                columns[x][k] -= cached[x][k];
    };
    for (int y = std::max(0, y0 - r); y <= std::min(h - 1, y0 + r); ++y)
        addRow(y);
    for (int y = y0; y < y1; ++y) {
        Sums run{};
        for (int x = 0; x <= std::min(w - 1, r); ++x)
            for (int k = 0; k < K; ++k)
                run[k] += columns[x][k];
        for (int x = 0; x < w; ++x) {
            emit(x, y, run);
            if (x + r + 1 < w)
                for (int k = 0; k < K; ++k)
                    run[k] += columns[x + r + 1][k];
            if (x - r >= 0)
                for (int k = 0; k < K; ++k)
                    run[k] -= columns[x - r][k];
        }
        if (y - r >= 0)
            removeRow(y - r);
        if (y + r + 1 < h)
            addRow(y + r + 1);
    }
}

// Depth centred on its weighted mean, with its weights; 0 weight (and 0 depth) where nothing was measured.
// The weights count in the window statistics and say whether a pixel has a measurement of its own (>= 0.5
// after interpolation), which is what gets an output depth.
struct CentredDepth {
    Plane<float> depth;
    Plane<float> weight;
    double offset = 0.0; // add back to get the depth's own units
    bool any = false;
};

CentredDepth centre(const Plane<float>& depth, const Plane<float>* weight) {
    CentredDepth c{Plane<float>(depth.width, depth.height), Plane<float>(depth.width, depth.height), 0.0,
                   false};
    double sum = 0.0, total = 0.0;
    for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
        const float w = weight ? std::clamp(weight->pixels[i], 0.0f, 1.0f) : 1.0f;
        if (!frame::isMeasured(depth.pixels[i]) || !(w >= kMinWeight))
            continue;
        c.weight.pixels[i] = w;
        sum += static_cast<double>(w) * depth.pixels[i];
        total += w;
    }
    if (total <= 0.0)
        return c;
    c.any = true;
    c.offset = sum / total;
    for (std::size_t i = 0; i < depth.pixels.size(); ++i)
        if (c.weight.pixels[i] > 0.0f)
            c.depth.pixels[i] = static_cast<float>(depth.pixels[i] - c.offset);
    return c;
}

// Each window's weighted linear model depth = a * guide + b, premultiplied by its aggregation weight.
struct WindowModels {
    Plane<float> wa, wb, w;
};

WindowModels windowModels(const Plane<float>& guide, const CentredDepth& d, int r,
                          const GuidedFilterParams& p) {
    const int width = guide.width, height = guide.height;
    WindowModels m{Plane<float>(width, height), Plane<float>(width, height), Plane<float>(width, height)};
    const double eps = std::max(static_cast<double>(p.epsilon), 0.0);
    const double fitVariance = std::max(static_cast<double>(p.fitNoise) * p.fitNoise, 1e-30);
    const auto quantities = [&](int x, int y) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        const double wt = d.weight.pixels[i], g = guide.pixels[i], z = d.depth.pixels[i];
        const double wg = wt * g, wz = wt * z;
        return std::array<double, 6>{wt, wg, wz, wg * g, wg * z, wz * z};
    };
    const auto emit = [&](int x, int y, const std::array<double, 6>& s) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        if (!(s[0] >= kMinWeight)) {
            m.wa.pixels[i] = m.wb.pixels[i] = m.w.pixels[i] = 0.0f;
            return;
        }
        const double n = s[0], meanG = s[1] / n, meanZ = s[2] / n;
        const double varG = std::max(s[3] / n - meanG * meanG, 0.0);
        const double cov = s[4] / n - meanG * meanZ;
        const double varZ = std::max(s[5] / n - meanZ * meanZ, 0.0);
        const double a = cov / (varG + eps);
        const double b = meanZ - a * meanG;
        double weight = 1.0;
        if (p.fitWeighted) {
            // The ridge regression's minimum, E[(a g + b - z)^2] + epsilon a^2 = var(z) - a cov: a window
            // that needs a steep model (a guide edge it must follow) pays for it, as does a poor fit.
            const double cost = std::max(varZ - a * cov, 0.0);
            const double t = 1.0 + cost / fitVariance;
            weight = std::max(1.0 / (t * t), static_cast<double>(kMinFitWeight));
        }
        m.wa.pixels[i] = static_cast<float>(weight * a);
        m.wb.pixels[i] = static_cast<float>(weight * b);
        m.w.pixels[i] = static_cast<float>(weight);
    };
    parallelRanges(height, kRowsPerPiece,
                   [&](int y0, int y1) { windowSums<6>(width, height, r, y0, y1, quantities, emit); });
    return m;
}

// Averages the window models over each pixel's windows and hands emit(x, y, a, b, hasModel) the result.
template <class Emit> void averageModels(const WindowModels& m, int r, const Emit& emit) {
    const int width = m.w.width, height = m.w.height;
    const auto quantities = [&](int x, int y) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        return std::array<double, 3>{m.wa.pixels[i], m.wb.pixels[i], m.w.pixels[i]};
    };
    const auto average = [&](int x, int y, const std::array<double, 3>& s) {
        if (s[2] > 0.0)
            emit(x, y, s[0] / s[2], s[1] / s[2], true);
        else
            emit(x, y, 0.0, 0.0, false);
    };
    parallelRanges(height, kRowsPerPiece,
                   [&](int y0, int y1) { windowSums<3>(width, height, r, y0, y1, quantities, average); });
}

// The output depth of one pixel: the filtered value where it is a usable depth, else the pixel's own
// (interpolated) measurement; 0 where the pixel has no measurement of its own.
float outputDepth(double filtered, bool hasModel, float ownCentred, float ownWeight, double offset) {
    if (!(ownWeight >= 0.5f))
        return 0.0f;
    const auto q = static_cast<float>(filtered + offset);
    if (hasModel && frame::isMeasured(q))
        return q;
    const auto own = static_cast<float>(ownCentred + offset);
    return frame::isMeasured(own) ? own : 0.0f;
}

// The full filter on one grid, `d` already centred and on the guide's grid.
Plane<float> filterOnGrid(const Plane<float>& guide, const CentredDepth& d, const GuidedFilterParams& p) {
    Plane<float> out(guide.width, guide.height);
    const int r = std::max(p.radius, 1);
    const WindowModels models = windowModels(guide, d, r, p);
    averageModels(models, r, [&](int x, int y, double a, double b, bool hasModel) {
        const std::size_t i = static_cast<std::size_t>(y) * guide.width + x;
        out.pixels[i] =
            outputDepth(a * guide.pixels[i] + b, hasModel, d.depth.pixels[i], d.weight.pixels[i], d.offset);
    });
    return out;
}

Plane<float> weightedDepth(const CentredDepth& d) {
    Plane<float> weighted(d.depth.width, d.depth.height);
    for (std::size_t i = 0; i < weighted.pixels.size(); ++i)
        weighted.pixels[i] = d.depth.pixels[i] * d.weight.pixels[i];
    return weighted;
}

// `d` (centred, at the sensor's size) scaled to `size` with masked bilinear / area interpolation: weights
// and weighted depths are resampled and divided, so a hole never drags its neighbours towards 0.
CentredDepth resampleCentred(const CentredDepth& d, cv::Size size) {
    CentredDepth out{Plane<float>(size.width, size.height), Plane<float>(size.width, size.height), d.offset,
                     d.any};
    resized(asMat(weightedDepth(d)), size).copyTo(asMat(out.depth));
    resized(asMat(d.weight), size).copyTo(asMat(out.weight));
    for (std::size_t i = 0; i < out.depth.pixels.size(); ++i) {
        const float w = out.weight.pixels[i];
        if (w >= kMinWeight) {
            out.depth.pixels[i] /= w;
        } else {
            out.depth.pixels[i] = 0.0f;
            out.weight.pixels[i] = 0.0f;
        }
    }
    return out;
}

// The fast filter's coefficients on its grid, interleaved (a, b): output = a * guide + b (+ offset).
using GridModels = cv::Mat; // CV_32FC2

// Nodes without a model (no measurement within their windows) copy the nearest node that has one, so that
// plain bilinear interpolation of the grid never mixes in an undefined model. Such pixels are holes of the
// output anyway unless a measurement lies within one grid cell.
void fillMissingModels(GridModels& g, std::vector<std::uint8_t>& has) {
    const int w = g.cols, h = g.rows;
    auto* ab = g.ptr<cv::Vec2f>(0);
    std::vector<int> frontier;
    for (int i = 0; i < w * h; ++i)
        if (has[static_cast<std::size_t>(i)])
            frontier.push_back(i);
    for (std::size_t k = 0; k < frontier.size(); ++k) { // breadth-first: nearest in grid steps
        const int i = frontier[k], x = i % w, y = i / w;
        const int neighbours[4] = {x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1, y > 0 ? i - w : -1,
                                   y + 1 < h ? i + w : -1};
        for (int n : neighbours) {
            if (n < 0 || has[static_cast<std::size_t>(n)])
                continue;
            has[static_cast<std::size_t>(n)] = 1;
            ab[n] = ab[i];
            frontier.push_back(n);
        }
    }
}

GridModels gridModels(const Plane<float>& guide, const CentredDepth& d, int r, const GuidedFilterParams& p) {
    GridModels g(guide.height, guide.width, CV_32FC2);
    auto* ab = g.ptr<cv::Vec2f>(0);
    std::vector<std::uint8_t> has(static_cast<std::size_t>(guide.width) * guide.height);
    averageModels(windowModels(guide, d, r, p), r, [&](int x, int y, double a, double b, bool hasModel) {
        const std::size_t i = static_cast<std::size_t>(y) * guide.width + x;
        ab[i] = {static_cast<float>(a), static_cast<float>(b)};
        has[i] = hasModel;
    });
    fillMissingModels(g, has);
    return g;
}

// The sensor's own interpolated measurement at output pixel (x, y), for the rare pixel whose filtered value
// is not a usable depth.
float ownDepth(const CentredDepth& sensor, int x, int y, int width, int height) {
    const double sx = std::clamp((x + 0.5) * sensor.depth.width / width - 0.5, 0.0, sensor.depth.width - 1.0);
    const double sy =
        std::clamp((y + 0.5) * sensor.depth.height / height - 0.5, 0.0, sensor.depth.height - 1.0);
    const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
    const int x1 = std::min(x0 + 1, sensor.depth.width - 1), y1 = std::min(y0 + 1, sensor.depth.height - 1);
    const double fx = sx - x0, fy = sy - y0;
    double wz = 0.0, w = 0.0;
    for (const auto& [px, py, f] :
         {std::tuple{x0, y0, (1 - fx) * (1 - fy)}, std::tuple{x1, y0, fx * (1 - fy)},
          std::tuple{x0, y1, (1 - fx) * fy}, std::tuple{x1, y1, fx * fy}}) {
        wz += f * sensor.weight.at(px, py) * sensor.depth.at(px, py);
        w += f * sensor.weight.at(px, py);
    }
    const auto own = static_cast<float>(w > 0.0 ? wz / w + sensor.offset : 0.0);
    return frame::isMeasured(own) ? own : 0.0f;
}

// One output row: a * guide + b + offset where the pixel was measured, else 0. Returns how many measured
// pixels got no usable depth (NaN, inf, <= 0). Branch-free over restrict pointers, so it vectorises.
int applyRow(const float* __restrict ab, const float* __restrict weight, const std::uint8_t* __restrict guide,
             float* __restrict out, int n, float offset) {
    int unusable = 0;
    for (int x = 0; x < n; ++x) {
        const float g = static_cast<float>(guide[x]) * (1.0f / 255.0f);
        const float q = ab[2 * x] * g + ab[2 * x + 1] + offset; // computed everywhere: a select, not a branch
        const int own = weight[x] >= 0.5f;
        const int usable = (q > 0.0f) & (q < kFarthest); // bitwise: no control flow
        out[x] = own ? q : 0.0f;
        unusable += own & (usable ^ 1);
    }
    return unusable;
}

// The fast filter's last step: coefficients interpolated bilinearly to every output pixel (OpenCV's
// vectorised resize), applied to the full-resolution guide where the sensor's interpolated weight says the
// pixel was measured.
void applyGridModels(const GridModels& g, const cv::Mat& guide8, const CentredDepth& sensor,
                     Plane<float>& out) {
    const cv::Size size(out.width, out.height);
    cv::Mat ab, weight;
    cv::resize(g, ab, size, 0, 0, cv::INTER_LINEAR);
    cv::resize(asMat(sensor.weight), weight, size, 0, 0, cv::INTER_LINEAR);
    const auto offset = static_cast<float>(sensor.offset);
    parallelRanges(out.height, kRowsPerPiece, [&](int begin, int end) {
        for (int y = begin; y < end; ++y) {
            const float* w = weight.ptr<float>(y);
            float* row = out.pixels.data() + static_cast<std::size_t>(y) * out.width;
            const int unusable =
                applyRow(ab.ptr<float>(y), w, guide8.ptr<std::uint8_t>(y), row, out.width, offset);
            for (int x = 0; unusable > 0 && x < out.width; ++x)
                if (w[x] >= 0.5f && !frame::isMeasured(row[x]))
                    row[x] = ownDepth(sensor, x, y, out.width, out.height);
        }
    });
}

} // namespace

Plane<float> maskedGuidedFilter(const Plane<float>& guide, const Plane<float>& depth,
                                const Plane<float>& weight, const GuidedFilterParams& params) {
    if (guide.width != depth.width || guide.height != depth.height ||
        weight.pixels.size() != depth.pixels.size() || depth.empty())
        return Plane<float>(depth.width, depth.height);
    const CentredDepth d = centre(depth, &weight);
    if (!d.any)
        return Plane<float>(depth.width, depth.height);
    return filterOnGrid(guide, d, params);
}

void GuidedUpsampler::setGuide(GrayView guide, int outputWidth, int outputHeight,
                               const GuidedFilterParams& params) {
    params_ = params;
    params_.subsample = std::max(params.subsample, 1);
    if (guide.empty() || outputWidth <= 0 || outputHeight <= 0) {
        guideOutput_ = {};
        guideGrid_ = {};
        return;
    }
    const cv::Mat source(guide.height, guide.width, CV_8U, const_cast<std::uint8_t*>(guide.pixels),
                         static_cast<std::size_t>(guide.stride));
    if (guideOutput_.width != outputWidth || guideOutput_.height != outputHeight)
        guideOutput_ = Plane<std::uint8_t>(outputWidth, outputHeight);
    resized(source, {outputWidth, outputHeight}).copyTo(asMat(guideOutput_));
    const int gridWidth = (outputWidth + params_.subsample - 1) / params_.subsample;
    const int gridHeight = (outputHeight + params_.subsample - 1) / params_.subsample;
    if (guideGrid_.width != gridWidth || guideGrid_.height != gridHeight)
        guideGrid_ = Plane<float>(gridWidth, gridHeight);
    resized(asMat(guideOutput_), {gridWidth, gridHeight}).convertTo(asMat(guideGrid_), CV_32F, 1.0 / 255.0);
}

frame::DepthData GuidedUpsampler::upsample(const frame::DepthData& depth) const {
    const int width = guideOutput_.width, height = guideOutput_.height;
    if (guideOutput_.empty() || depth.depthMeters.empty())
        return depth;
    frame::DepthData out{Plane<float>(width, height), {}, depth.confidenceEstimated};
    if (!depth.confidence.empty() && depth.confidence.pixels.size() == depth.depthMeters.pixels.size()) {
        out.confidence = Plane<std::uint8_t>(width, height);
        cv::resize(asMat(depth.confidence), asMat(out.confidence), {width, height}, 0, 0, cv::INTER_LINEAR);
    }
    const CentredDepth sensor = centre(depth.depthMeters, nullptr);
    if (!sensor.any)
        return out;
    const CentredDepth onGrid = resampleCentred(sensor, {guideGrid_.width, guideGrid_.height});
    if (params_.subsample == 1) {
        out.depthMeters = filterOnGrid(guideGrid_, onGrid, params_);
        return out;
    }
    const int r =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(params_.radius) / params_.subsample)));
    applyGridModels(gridModels(guideGrid_, onGrid, r, params_), asMat(guideOutput_), sensor, out.depthMeters);
    return out;
}

frame::DepthData guidedUpsample(const frame::DepthData& depth, GrayView guide, int outputWidth,
                                int outputHeight, const GuidedFilterParams& params) {
    GuidedUpsampler upsampler;
    upsampler.setGuide(guide, outputWidth, outputHeight, params);
    return upsampler.upsample(depth);
}

} // namespace dc::processing
