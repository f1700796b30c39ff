#include "processing/global_smoother.h"

#include "processing/parallel.h"
#include "processing/resample.h"
#include "processing/tridiagonal.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace dc::processing {

namespace {

// Lines solved in lockstep, one per lane: kLanes neighbouring rows in the horizontal sweeps, kLanes
// neighbouring columns in the vertical ones, as two AVX vectors (Octet) or four SSE ones (Quad): independent
// chains of work that hide the latency of the division each elimination step waits for.
constexpr int kLanes = 16;
using Quad = float __attribute__((vector_size(4 * sizeof(float))));
using Octet = float __attribute__((vector_size(8 * sizeof(float))));

// A smoothed weight below this means no sample reached the pixel: its own data is used instead.
constexpr float kMinSolvedWeight = 1e-6f;
// Data weight per ARKit confidence level: a low-confidence sample is filled in from its neighbours rather
// than trusted; medium counts half as much as high.
constexpr float kConfidenceWeight[3] = {0.0f, 0.5f, 1.0f};
constexpr int kRowsPerPiece = 16;

int roundUp(int n, int multiple) {
    return (n + multiple - 1) / multiple * multiple;
}

// FGS's schedule: the smoothness of iteration t of T falls by 4 from one to the next and the iterations
// sum to 1.5 lambda, so that the first sweeps carry values far and the later ones repair the streaks that
// alternating 1-D solves leave.
float iterationLambda(float lambda, int t, int iterations) {
    return static_cast<float>(lambda * 1.5 * std::pow(4.0, iterations - 1 - t) /
                              (std::pow(4.0, iterations) - 1.0));
}

struct Grid {
    int width = 0, height = 0, paddedWidth = 0, paddedHeight = 0;
    std::vector<float> dataSum, dataWeight; // confidence-weighted data and its weight
    std::vector<float> sum, weight;         // the same, smoothed in place by a pass
    std::vector<float> edgeH, edgeV;        // neighbour weights of the pass: to the right, below
    std::vector<float> value;               // the last pass's depth, centred
    ColorView guide;                        // the colour at the grid's size (not owned)
    bool uniformWeight = false;             // every pixel's data weight is the same: weight is not solved

    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * paddedWidth + x; }
};

// A new size zeroes every plane: the padding (whole vectors of lanes) must stay 0, which no weight couples
// to a real pixel and every solve keeps at 0.
void resize(Grid& g, int width, int height) {
    if (g.width == width && g.height == height)
        return;
    g.width = width;
    g.height = height;
    g.paddedWidth = roundUp(width, kLanes);
    g.paddedHeight = roundUp(height, kLanes);
    const std::size_t n = static_cast<std::size_t>(g.paddedWidth) * g.paddedHeight;
    for (std::vector<float>* plane :
         {&g.dataSum, &g.dataWeight, &g.sum, &g.weight, &g.edgeH, &g.edgeV, &g.value})
        plane->assign(n, 0.0f);
}

void rowsInParallel(int height, const std::function<void(int y)>& row) {
    parallelRanges(height, kRowsPerPiece, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            row(y);
    });
}

// The per-pixel kernels are also built for x86-64-v3 (AVX2, FMA) and chosen at run time: twice the lanes
// per instruction where the CPU has them. flatten inlines what they call into each version. Sanitizer
// builds keep one version: the choice is an ifunc resolver, which runs while the program is relocated,
// before the sanitizer's runtime exists, and ThreadSanitizer's hook at its entry crashes there.
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
#define DC_VECTOR_KERNEL [[gnu::flatten]]
#else
#define DC_VECTOR_KERNEL [[gnu::target_clones("arch=x86-64-v3", "default"), gnu::flatten]]
#endif

// Squared Euclidean distances of n pixels' colours to their right neighbours' (h) and to the pixels below
// (v); h[n - 1] is never read.
DC_VECTOR_KERNEL void colorDistanceRow(const std::uint8_t* __restrict row,
                                       const std::uint8_t* __restrict below, float* __restrict h,
                                       float* __restrict v, int n) {
    for (int x = 0; x + 1 < n; ++x) {
        const int d0 = row[3 * x + 3] - row[3 * x], d1 = row[3 * x + 4] - row[3 * x + 1],
                  d2 = row[3 * x + 5] - row[3 * x + 2];
        h[x] = static_cast<float>(d0 * d0 + d1 * d1 + d2 * d2);
    }
    for (int x = 0; x < n; ++x) {
        const int d0 = below[3 * x] - row[3 * x], d1 = below[3 * x + 1] - row[3 * x + 1],
                  d2 = below[3 * x + 2] - row[3 * x + 2];
        v[x] = static_cast<float>(d0 * d0 + d1 * d1 + d2 * d2);
    }
}

// One neighbour weight: colour term 1 / (1 + (d / sigma)^8) from the squared distance d^2, times depth term
// 1 / (1 + (dz / sigma)^2)^2. A sigma of 0 enters as an inverse of 0, which makes its term exactly 1.
float neighbourWeight(float colorSquared, float inverseColorSigmaSquared, float dz, float inverseDepthSigma) {
    const float s = colorSquared * inverseColorSigmaSquared, s2 = s * s;
    const float t = dz * inverseDepthSigma, q = 1.0f + t * t;
    return 1.0f / ((1.0f + s2 * s2) * (q * q));
}

void transpose(Quad (&q)[4]) {
    const Quad ab0 = __builtin_shufflevector(q[0], q[1], 0, 4, 1, 5),
               ab1 = __builtin_shufflevector(q[0], q[1], 2, 6, 3, 7);
    const Quad cd0 = __builtin_shufflevector(q[2], q[3], 0, 4, 1, 5),
               cd1 = __builtin_shufflevector(q[2], q[3], 2, 6, 3, 7);
    q[0] = __builtin_shufflevector(ab0, cd0, 0, 1, 4, 5);
    q[1] = __builtin_shufflevector(ab0, cd0, 2, 3, 6, 7);
    q[2] = __builtin_shufflevector(ab1, cd1, 0, 1, 4, 5);
    q[3] = __builtin_shufflevector(ab1, cd1, 2, 3, 6, 7);
}

// The 8 x 8 transpose as AVX does it: pairs of rows interleaved, then pairs of pairs, then the halves of
// rows k and k + 4 exchanged (24 shuffles for 64 values, where 4 x 4 tiles take 32).
void transpose(Octet (&r)[8]) {
    Octet t[8], u[8];
    for (int k = 0; k < 8; k += 2) {
        t[k] = __builtin_shufflevector(r[k], r[k + 1], 0, 8, 1, 9, 4, 12, 5, 13);
        t[k + 1] = __builtin_shufflevector(r[k], r[k + 1], 2, 10, 3, 11, 6, 14, 7, 15);
    }
    for (int k = 0; k < 8; k += 4)
        for (int j = 0; j < 2; ++j) {
            u[k + 2 * j] = __builtin_shufflevector(t[k + j], t[k + j + 2], 0, 1, 8, 9, 4, 5, 12, 13);
            u[k + 2 * j + 1] = __builtin_shufflevector(t[k + j], t[k + j + 2], 2, 3, 10, 11, 6, 7, 14, 15);
        }
    for (int k = 0; k < 4; ++k) {
        r[k] = __builtin_shufflevector(u[k], u[k + 4], 0, 1, 2, 3, 8, 9, 10, 11);
        r[k + 4] = __builtin_shufflevector(u[k], u[k + 4], 4, 5, 6, 7, 12, 13, 14, 15);
    }
}

// kLanes rows of a plane (row stride `stride`) to and from lines[x * kLanes + lane], in square tiles of
// V's lanes (4 x 4 or 8 x 8).
template <class V, bool ToLines>
void interleave(float* rows, std::size_t stride, int paddedWidth, float* lines) {
    constexpr int n = sizeof(V) / sizeof(float);
    for (int group = 0; group < kLanes / n; ++group)
        for (int x = 0; x < paddedWidth; x += n) {
            V tile[n];
            for (int k = 0; k < n; ++k)
                loadLanes(tile[k], ToLines ? rows + (n * group + k) * stride + x
                                           : lines + static_cast<std::size_t>(x + k) * kLanes + n * group);
            transpose(tile);
            for (int k = 0; k < n; ++k)
                storeLanes(ToLines ? lines + static_cast<std::size_t>(x + k) * kLanes + n * group
                                   : rows + (n * group + k) * stride + x,
                           tile[k]);
        }
}

// The neighbour weights of the kLanes rows of block b: vertical ones in place, horizontal ones into `rows`
// (kLanes rows of the padded width, then 2 more for each row's colour distances), then interleaved as the
// horizontal sweeps read them. The colour distances are computed here, row by row, rather than kept in two
// planes: reading those planes from memory cost more than computing them again for each pass.
DC_VECTOR_KERNEL void weightBlock(Grid& g, int b, float inverseColor, float inverseDepth, float* rows) {
    const std::size_t stride = static_cast<std::size_t>(g.paddedWidth);
    float* __restrict ch = rows + kLanes * stride;
    float* __restrict cv = ch + stride;
    for (int y = b * kLanes; y < std::min((b + 1) * kLanes, g.height); ++y) {
        const std::size_t i = g.index(0, y);
        const std::uint8_t* colour = g.guide.pixels + y * g.guide.stride;
        colorDistanceRow(colour, y + 1 < g.height ? colour + g.guide.stride : colour, ch, cv, g.width);
        const float* __restrict z = g.value.data() + i;
        const float* __restrict below = y + 1 < g.height ? z + g.paddedWidth : z;
        float* __restrict h = rows + (y - b * kLanes) * stride;
        float* __restrict v = g.edgeV.data() + i;
        for (int x = 0; x + 1 < g.width; ++x)
            h[x] = neighbourWeight(ch[x], inverseColor, z[x + 1] - z[x], inverseDepth);
        for (int x = 0; x < g.width; ++x)
            v[x] = neighbourWeight(cv[x], inverseColor, below[x] - z[x], inverseDepth);
    }
    interleave<Quad, true>(rows, stride, g.paddedWidth, g.edgeH.data() + b * kLanes * stride);
}

// The pass's neighbour weights, computed once per pass (not once per sweep).
void passWeights(Grid& g, const SmootherPass& pass) {
    const float ic = pass.colorSigma > 0.0f ? 1.0f / (pass.colorSigma * pass.colorSigma) : 0.0f;
    const float id = pass.depthSigma > 0.0f ? 1.0f / pass.depthSigma : 0.0f;
    parallelRanges(g.paddedHeight / kLanes, 1, [&](int b0, int b1) {
        thread_local std::vector<float> rows;
        rows.assign(static_cast<std::size_t>(g.paddedWidth) * (kLanes + 2), 0.0f);
        for (int b = b0; b < b1; ++b)
            weightBlock(g, b, ic, id, rows.data());
    });
}

// The planes a sweep solves: the data and its weight, or the data alone where the weight is the same
// everywhere (g.uniformWeight), since smoothing a constant leaves it unchanged.
std::size_t planesOf(const Grid& g) {
    return g.uniformWeight ? 1 : 2;
}

// One horizontal sweep of the kLanes rows of block b over K planes: to lines, solved, back. `lines` holds
// 2 x kLanes rows. The pass's first sweep reads the data itself (fromData), which spares copying it into
// sum and weight.
template <class V, std::size_t K>
void horizontalBlock(Grid& g, int b, float scale, bool fromData, float* lines, float* forward) {
    const std::size_t stride = static_cast<std::size_t>(g.paddedWidth), lineSize = stride * kLanes;
    const std::size_t first = static_cast<std::size_t>(b) * lineSize;
    const std::array<std::vector<float>*, 2> from = {fromData ? &g.dataSum : &g.sum,
                                                     fromData ? &g.dataWeight : &g.weight};
    const std::array<std::vector<float>*, 2> to = {&g.sum, &g.weight};
    std::array<float*, K> rhs;
    for (std::size_t k = 0; k < K; ++k) {
        rhs[k] = lines + k * lineSize;
        interleave<V, true>(from[k]->data() + first, stride, g.paddedWidth, rhs[k]);
    }
    solvePathLaplacian<V, K, kLanes * sizeof(float) / sizeof(V)>(g.width, g.edgeH.data() + first, rhs, kLanes,
                                                                 scale, forward);
    for (std::size_t k = 0; k < K; ++k)
        interleave<V, false>(to[k]->data() + first, stride, g.paddedWidth, rhs[k]);
}

// One vertical sweep of the kLanes columns from x0 over K planes, in place.
template <class V, std::size_t K> void verticalStrip(Grid& g, std::size_t x0, float scale, float* forward) {
    std::array<float*, K> rhs;
    rhs[0] = g.sum.data() + x0;
    if constexpr (K > 1)
        rhs[1] = g.weight.data() + x0;
    solvePathLaplacian<V, K, kLanes * sizeof(float) / sizeof(V)>(g.height, g.edgeV.data() + x0, rhs,
                                                                 g.paddedWidth, scale, forward);
}

// The sweeps built twice: for x86-64-v3 (AVX2, FMA) with Octets, and for any x86-64 with Quads, the widths
// each instruction set has registers for (a wider generic vector is split through memory). flatten
// inlines the solve into each, so that it is compiled for that instruction set. Each for one plane and for
// two.
struct Sweeps {
    void (*horizontal[2])(Grid&, int b, float scale, bool fromData, float* lines);
    void (*vertical[2])(Grid&, std::size_t x0, float scale);
};

// Each thread's scratch for the elimination's multipliers: n elements of kLanes floats.
float* forwardScratch(int n) {
    thread_local std::vector<float> forward;
    forward.resize(static_cast<std::size_t>(n) * kLanes);
    return forward.data();
}

template <std::size_t K>
[[gnu::target("arch=x86-64-v3"), gnu::flatten]] void horizontalAvx2(Grid& g, int b, float scale,
                                                                    bool fromData, float* lines) {
    horizontalBlock<Octet, K>(g, b, scale, fromData, lines, forwardScratch(g.paddedWidth));
}
template <std::size_t K>
[[gnu::target("arch=x86-64-v3"), gnu::flatten]] void verticalAvx2(Grid& g, std::size_t x0, float scale) {
    verticalStrip<Octet, K>(g, x0, scale, forwardScratch(g.paddedHeight));
}
template <std::size_t K>
[[gnu::flatten]] void horizontalSse2(Grid& g, int b, float scale, bool fromData, float* lines) {
    horizontalBlock<Quad, K>(g, b, scale, fromData, lines, forwardScratch(g.paddedWidth));
}
template <std::size_t K> [[gnu::flatten]] void verticalSse2(Grid& g, std::size_t x0, float scale) {
    verticalStrip<Quad, K>(g, x0, scale, forwardScratch(g.paddedHeight));
}

const Sweeps& sweeps() {
    static const Sweeps chosen =
        __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")
            ? Sweeps{{horizontalAvx2<1>, horizontalAvx2<2>}, {verticalAvx2<1>, verticalAvx2<2>}}
            : Sweeps{{horizontalSse2<1>, horizontalSse2<2>}, {verticalSse2<1>, verticalSse2<2>}};
    return chosen;
}

void horizontalSweep(Grid& g, float scale, bool fromData) {
    const auto sweep = sweeps().horizontal[planesOf(g) - 1];
    parallelRanges(g.paddedHeight / kLanes, 1, [&](int b0, int b1) {
        thread_local std::vector<float> lines;
        lines.resize(2 * static_cast<std::size_t>(g.paddedWidth) * kLanes);
        for (int b = b0; b < b1; ++b)
            sweep(g, b, scale, fromData, lines.data());
    });
}

void verticalSweep(Grid& g, float scale) {
    const auto sweep = sweeps().vertical[planesOf(g) - 1];
    parallelRanges(g.paddedWidth / kLanes, 1, [&](int s0, int s1) {
        for (int s = s0; s < s1; ++s)
            sweep(g, static_cast<std::size_t>(s) * kLanes, scale);
    });
}

// value = sum / weight, or the data's own ratio where the smoothed weight is too small to divide by (0 where
// there is no data either). Branch-free over restrict pointers, so that it vectorises, with one division.
DC_VECTOR_KERNEL void ratioRow(const float* __restrict sum, const float* __restrict weight,
                               const float* __restrict dataSum, const float* __restrict dataWeight,
                               float* __restrict value, int n) {
    for (int x = 0; x < n; ++x) {
        const bool solved = weight[x] > kMinSolvedWeight;
        const float numerator = solved ? sum[x] : dataSum[x];
        const float denominator = solved ? weight[x] : std::max(dataWeight[x], FLT_MIN);
        value[x] = solved || dataWeight[x] > 0.0f ? numerator / denominator : 0.0f;
    }
}

// A pass's smoothing: its weights from the colour distances and the previous pass's depth, and the data
// and its weight smoothed into sum and weight.
void smoothPass(Grid& g, const SmootherPass& pass) {
    passWeights(g, pass);
    for (int t = 0; t < pass.iterations; ++t) {
        const float scale = iterationLambda(pass.lambda, t, pass.iterations);
        horizontalSweep(g, scale, t == 0);
        verticalSweep(g, scale);
    }
}

// Row y of a pass's result (smoothed data over smoothed weight) into `value`. A pixel that no weight
// reached keeps its own data (0, the mean, where it has none).
void resultRow(const Grid& g, int y, float* value) {
    const std::size_t i = g.index(0, y);
    const float* weight = (g.uniformWeight ? g.dataWeight : g.weight).data() + i;
    ratioRow(g.sum.data() + i, weight, g.dataSum.data() + i, g.dataWeight.data() + i, value, g.width);
}

// One pass, its result as the grid's new depth.
void runPass(Grid& g, const SmootherPass& pass) {
    if (pass.iterations <= 0)
        return;
    smoothPass(g, pass);
    rowsInParallel(g.height, [&](int y) { resultRow(g, y, g.value.data() + g.index(0, y)); });
}

// The data as the grid's depth, for the first pass's weights (which use colour only) and for a grid that no
// pass smooths.
void dataAsValue(Grid& g) {
    rowsInParallel(g.height, [&](int y) {
        const std::size_t i = g.index(0, y);
        ratioRow(g.dataSum.data() + i, g.dataWeight.data() + i, g.dataSum.data() + i, g.dataWeight.data() + i,
                 g.value.data() + i, g.width);
    });
}

} // namespace

namespace {

// The colour-weighted median of `value` (see GlobalSmootherParams::weightedMedianRadius) into `out`.
void weightedMedian(const cv::Mat& value, ColorView guide, int radius, float sigma, cv::Mat& out) {
    const float inverseSigmaSquared = 1.0f / std::max(sigma * sigma, 1e-6f);
    rowsInParallel(value.rows, [&](int y) {
        std::vector<std::pair<float, float>> votes;
        for (int x = 0; x < value.cols; ++x) {
            const std::uint8_t* centre = guide.pixels + y * guide.stride + 3 * x;
            votes.clear();
            float total = 0.0f;
            for (int v = std::max(y - radius, 0); v <= std::min(y + radius, value.rows - 1); ++v)
                for (int u = std::max(x - radius, 0); u <= std::min(x + radius, value.cols - 1); ++u) {
                    const std::uint8_t* other = guide.pixels + v * guide.stride + 3 * u;
                    float d2 = 0.0f;
                    for (int c = 0; c < 3; ++c)
                        d2 += static_cast<float>((other[c] - centre[c]) * (other[c] - centre[c]));
                    const float w = 1.0f / (1.0f + d2 * inverseSigmaSquared);
                    votes.emplace_back(value.at<float>(v, u), w);
                    total += w;
                }
            std::sort(votes.begin(), votes.end());
            float cumulative = 0.0f;
            std::size_t k = 0;
            while (k + 1 < votes.size() && (cumulative += votes[k].second) < 0.5f * total)
                ++k;
            out.at<float>(y, x) = votes[k].first;
        }
    });
}

} // namespace

struct GlobalSmoother::Buffers {
    Grid sensor, output;
    double offset = 0.0;                    // the data's weighted mean, subtracted while solving
    std::vector<std::uint8_t> sensorValid;  // 1 where the input was measured
    std::vector<std::uint8_t> sensorGuide;  // the guide reduced to the sensor's size, packed
    BilinearTaps tapsX, tapsY;              // output pixel -> sensor samples
    std::vector<std::uint8_t> measuredMask; // 1 where the measured samples' bilinear weight is >= 0.5
    std::vector<float> medianValue;         // a final median other than 3 x 3, output size
    std::vector<float> unsnapped;           // the output depth before snapEdges()
    // The output's last pass left its result in sum and weight: finish() computes it row by row as it
    // needs it, rather than writing a plane and reading it back.
    bool resultPending = false;

    bool prepareSensor(const frame::DepthData& depth);
    void reduceGuide(ColorView guide);
    // A thread's last two sensor rows interpolated to the output width (see interpolatedRow).
    struct InterpolatedRows {
        std::vector<float> data;
        int row[2] = {-1, -1};
        int older = 0;
    };
    const float* interpolatedRow(int r, InterpolatedRows& cache) const;
    void upsampleSensor(float footprintSigma);
    void runOutputPasses(const GlobalSmootherParams& params);
    const float* medianRow(int y0, int y, std::vector<float>& scratch);
    bool otherMedian(const GlobalSmootherParams& params, ColorView guide);
    void finish(const GlobalSmootherParams& params, ColorView guide, frame::DepthData& out);
    void snapEdges(float range, frame::DepthData& out);
};

bool GlobalSmoother::Buffers::prepareSensor(const frame::DepthData& depth) {
    const frame::Plane<float>& d = depth.depthMeters;
    const bool hasConfidence = depth.confidence.pixels.size() == d.pixels.size();
    resize(sensor, d.width, d.height);
    sensorValid.assign(d.pixels.size(), 0);
    double sum = 0.0, total = 0.0, validSum = 0.0, validCount = 0.0;
    for (std::size_t i = 0; i < d.pixels.size(); ++i) {
        if (!frame::isMeasured(d.pixels[i]))
            continue;
        sensorValid[i] = 1;
        const float w =
            hasConfidence ? kConfidenceWeight[std::min<int>(depth.confidence.pixels[i], 2)] : 1.0f;
        sum += static_cast<double>(w) * d.pixels[i];
        total += w;
        validSum += d.pixels[i];
        validCount += 1.0;
    }
    if (validCount == 0.0)
        return false;
    // A frame measured only with low confidence still has a shape: trust every sample alike then.
    const bool trustAll = total <= 0.0;
    offset = trustAll ? validSum / validCount : sum / total;
    float lowest = FLT_MAX, highest = 0.0f;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * d.width + x, at = sensor.index(x, y);
            const float w = !sensorValid[i] ? 0.0f
                            : trustAll || !hasConfidence
                                ? 1.0f
                                : kConfidenceWeight[std::min<int>(depth.confidence.pixels[i], 2)];
            sensor.dataWeight[at] = w;
            sensor.dataSum[at] = w > 0.0f ? static_cast<float>(w * (d.pixels[i] - offset)) : 0.0f;
            lowest = std::min(lowest, w);
            highest = std::max(highest, w);
        }
    // Every sample measured and weighted alike (dense data): its weight need not be smoothed.
    sensor.uniformWeight = lowest == highest;
    return true;
}

void GlobalSmoother::Buffers::reduceGuide(ColorView guide) {
    output.guide = guide;
    const cv::Mat full(guide.height, guide.width, CV_8UC3, const_cast<std::uint8_t*>(guide.pixels),
                       static_cast<std::size_t>(guide.stride));
    sensorGuide.resize(static_cast<std::size_t>(sensor.width) * sensor.height * 3);
    resized(full, {sensor.width, sensor.height})
        .copyTo(cv::Mat(sensor.height, sensor.width, CV_8UC3, sensorGuide.data()));
    sensor.guide = {sensorGuide.data(), sensor.width, sensor.height,
                    static_cast<std::ptrdiff_t>(sensor.width) * 3};
}

namespace {

// One sensor row interpolated to the output width (see interpolateRows): z the row's depth, m 1 where it was
// measured. Gathers through the taps over restrict pointers, so that it vectorises.
DC_VECTOR_KERNEL void interpolateRow(const float* __restrict z, const std::uint8_t* __restrict m,
                                     const int* __restrict first, const int* __restrict second,
                                     const float* __restrict fraction, float* __restrict sum,
                                     float* __restrict weight, float* __restrict lo, float* __restrict hi,
                                     int width) {
    for (int x = 0; x < width; ++x) {
        const int c0 = first[x], c1 = second[x];
        const float f = fraction[x], z0 = z[c0], z1 = z[c1];
        const float m0 = m[c0], m1 = m[c1];
        sum[x] = (1.0f - f) * m0 * z0 + f * m1 * z1;
        weight[x] = (1.0f - f) * m0 + f * m1;
        lo[x] = std::min(m0 > 0.0f ? z0 : FLT_MAX, m1 > 0.0f ? z1 : FLT_MAX);
        hi[x] = std::max(m0 > 0.0f ? z0 : -FLT_MAX, m1 > 0.0f ? z1 : -FLT_MAX);
    }
}

} // namespace

// Sensor row r interpolated horizontally to the output width, as 4 rows: the measured values' weighted sum
// and weight, and their minimum and maximum over the two taps (for the footprint's spread). A thread keeps
// the last two rows it interpolated: its output rows run in order and consecutive ones share sensor rows, so
// each sensor row is interpolated about once per thread, and no plane of them is written and read back.
const float* GlobalSmoother::Buffers::interpolatedRow(int r, InterpolatedRows& cache) const {
    const int width = output.width;
    const std::size_t rowSize = static_cast<std::size_t>(width) * 4;
    for (int k = 0; k < 2; ++k)
        if (cache.row[k] == r)
            return cache.data.data() + rowSize * k;
    const int k = cache.older;
    cache.older = 1 - k;
    cache.row[k] = r;
    float* sum = cache.data.data() + rowSize * k;
    interpolateRow(sensor.value.data() + sensor.index(0, r),
                   sensorValid.data() + static_cast<std::size_t>(r) * sensor.width, tapsX.first.data(),
                   tapsX.second.data(), tapsX.weight.data(), sum, sum + width, sum + 2 * width,
                   sum + 3 * width, width);
    return sum;
}

namespace {

// One output row from the two interpolated sensor rows around it (sum, weight, lo, hi, each n long), with
// the data's own depth as the row's value (what dataAsValue() would compute) for the first pass's weights.
DC_VECTOR_KERNEL void combineRows(const float* __restrict a, const float* __restrict b, float f,
                                  float inverseSigma, float* __restrict sum, float* __restrict weight,
                                  float* __restrict value, std::uint8_t* __restrict measuredMask, int n) {
    for (int x = 0; x < n; ++x) {
        const float lo = std::min(a[2 * n + x], b[2 * n + x]);
        const float hi = std::max(a[3 * n + x], b[3 * n + x]);
        const float spread = hi > lo ? (hi - lo) * inverseSigma : 0.0f;
        const float factor = 1.0f / (1.0f + spread * spread);
        const float m = (1.0f - f) * a[n + x] + f * b[n + x];
        measuredMask[x] = m >= 0.5f;
        sum[x] = ((1.0f - f) * a[x] + f * b[x]) * factor;
        weight[x] = m * factor;
        value[x] = weight[x] > 0.0f ? sum[x] / weight[x] : 0.0f;
    }
}

} // namespace

// The output grid's data: the bilinear upsampling of the sensor's (denoised) depth over its measured
// samples, each pixel's weight reduced where its footprint spans a depth edge; their ratio as its depth.
void GlobalSmoother::Buffers::upsampleSensor(float footprintSigma) {
    const int width = output.width;
    tapsX = bilinearTaps(sensor.width, width);
    tapsY = bilinearTaps(sensor.height, output.height);
    measuredMask.resize(static_cast<std::size_t>(width) * output.height);
    const float inverseSigma = footprintSigma > 0.0f ? 1.0f / footprintSigma : 0.0f;
    parallelRanges(output.height, kRowsPerPiece, [&](int y0, int y1) {
        thread_local InterpolatedRows cache;
        cache = {std::move(cache.data), {-1, -1}, 0}; // rows of an earlier frame or piece are stale
        cache.data.resize(static_cast<std::size_t>(width) * 8);
        for (int y = y0; y < y1; ++y) {
            const float* a = interpolatedRow(tapsY.first[y], cache);
            const float* b = interpolatedRow(tapsY.second[y], cache);
            const std::size_t at = output.index(0, y);
            combineRows(a, b, tapsY.weight[y], inverseSigma, output.dataSum.data() + at,
                        output.dataWeight.data() + at, output.value.data() + at,
                        measuredMask.data() + static_cast<std::size_t>(y) * width, width);
        }
    });
}

namespace {

// Output depth: the smoothed value where the bilinear map was measured and the value is a usable depth, else
// the bilinear data itself, else 0. Branch-free, so that it vectorises.
DC_VECTOR_KERNEL void outputRow(const float* __restrict smoothed, const float* __restrict dataSum,
                                const float* __restrict dataWeight,
                                const std::uint8_t* __restrict measuredMask, float offset,
                                float* __restrict out, int n) {
    for (int x = 0; x < n; ++x) {
        const float q = smoothed[x] + offset;
        const float own = dataSum[x] / std::max(dataWeight[x], FLT_MIN) + offset;
        const bool qUsable = q > 0.0f && q <= FLT_MAX, ownUsable = own > 0.0f && own <= FLT_MAX;
        const float chosen = qUsable ? q : ownUsable ? own : 0.0f;
        out[x] = measuredMask[x] ? chosen : 0.0f;
    }
}

} // namespace

namespace {

// Each column's three values (rows a, b, c) sorted, lo <= mid <= hi, at x + 1 for column x; the row's end
// columns are repeated once beyond it (OpenCV's replicated border).
DC_VECTOR_KERNEL void sortColumns(const float* __restrict a, const float* __restrict b,
                                  const float* __restrict c, float* __restrict lo, float* __restrict mid,
                                  float* __restrict hi, int n) {
    for (int x = 0; x < n; ++x) {
        const float small = std::min(a[x], b[x]), large = std::max(a[x], b[x]);
        lo[x + 1] = std::min(small, c[x]);
        mid[x + 1] = std::max(small, std::min(large, c[x]));
        hi[x + 1] = std::max(large, c[x]);
    }
    for (float* p : {lo, mid, hi}) {
        p[0] = p[1];
        p[n + 1] = p[n];
    }
}

float medianOf3(float p, float q, float r) {
    return std::max(std::min(p, q), std::min(std::max(p, q), r));
}

// The median of each 3 x 3 window from its columns sorted: of the nine values it is the median of the
// largest low, the median of the mids and the smallest high, which takes 7 comparisons per pixel instead
// of a sort of 9.
DC_VECTOR_KERNEL void medianOfColumns(const float* __restrict lo, const float* __restrict mid,
                                      const float* __restrict hi, float* __restrict out, int n) {
    for (int x = 0; x < n; ++x) {
        const float largestLow = std::max(std::max(lo[x], lo[x + 1]), lo[x + 2]);
        const float smallestHigh = std::min(std::min(hi[x], hi[x + 1]), hi[x + 2]);
        out[x] = medianOf3(largestLow, medianOf3(mid[x], mid[x + 1], mid[x + 2]), smallestHigh);
    }
}

} // namespace

// The 3 x 3 median of row y of the output's depth into `scratch` (7 rows of width + 2), returned; a thread
// runs its rows in order from y0. A pending result is computed into the first three scratch rows, each row
// once per run: row r in slot r % 3, so that at row y they hold rows y - 1, y and y + 1.
const float* GlobalSmoother::Buffers::medianRow(int y0, int y, std::vector<float>& scratch) {
    const int width = output.width, last = output.height - 1;
    const std::size_t n = static_cast<std::size_t>(width) + 2;
    scratch.resize(7 * n);
    const auto row = [&](int r) {
        r = std::clamp(r, 0, last);
        return resultPending ? scratch.data() + static_cast<std::size_t>(r % 3) * n
                             : output.value.data() + output.index(0, r);
    };
    if (resultPending)
        for (int r = y == y0 ? y - 1 : y + 1; r <= y + 1; ++r)
            resultRow(output, std::clamp(r, 0, last), row(r));
    const float* above = row(y - 1);
    const float* centre = row(y);
    const float* below = row(y + 1);
    float* sorted = scratch.data() + 3 * n;
    sortColumns(above, centre, below, sorted, sorted + n, sorted + 2 * n, width);
    medianOfColumns(sorted, sorted + n, sorted + 2 * n, sorted + 3 * n, width);
    return sorted + 3 * n;
}

// The median filters other than 3 x 3 into medianValue; false when the value goes out unfiltered.
bool GlobalSmoother::Buffers::otherMedian(const GlobalSmootherParams& params, ColorView guide) {
    const int width = output.width, height = output.height;
    const int side = params.medianPixels;
    if (params.weightedMedianRadius <= 0 && (side != 5 || width < side || height < side))
        return false;
    const cv::Mat value(height, width, CV_32F, output.value.data(),
                        static_cast<std::size_t>(output.paddedWidth) * 4);
    medianValue.resize(static_cast<std::size_t>(width) * height);
    cv::Mat filtered(height, width, CV_32F, medianValue.data());
    if (params.weightedMedianRadius > 0)
        weightedMedian(value, guide, params.weightedMedianRadius, params.weightedMedianSigma, filtered);
    else
        cv::medianBlur(value, filtered, side);
    return true;
}

// The final median (the 3 x 3 one computed row by row here, as each output row needs it) and the output.
void GlobalSmoother::Buffers::finish(const GlobalSmootherParams& params, ColorView guide,
                                     frame::DepthData& out) {
    const int width = output.width, height = output.height;
    const bool median3 =
        params.weightedMedianRadius <= 0 && params.medianPixels == 3 && width >= 3 && height >= 3;
    if (!median3 && resultPending) {
        rowsInParallel(height,
                       [&](int y) { resultRow(output, y, output.value.data() + output.index(0, y)); });
        resultPending = false;
    }
    const bool filtered = !median3 && otherMedian(params, guide);
    const auto offsetF = static_cast<float>(offset);
    parallelRanges(height, kRowsPerPiece, [&](int y0, int y1) {
        thread_local std::vector<float> scratch;
        for (int y = y0; y < y1; ++y) {
            const std::size_t row = static_cast<std::size_t>(y) * width, at = output.index(0, y);
            const float* value = median3    ? medianRow(y0, y, scratch)
                                 : filtered ? medianValue.data() + row
                                            : output.value.data() + at;
            outputRow(value, output.dataSum.data() + at, output.dataWeight.data() + at,
                      measuredMask.data() + row, offsetF, out.depthMeters.pixels.data() + row, width);
        }
    });
}

// The output's passes; the last one's result is left pending for finish().
void GlobalSmoother::Buffers::runOutputPasses(const GlobalSmootherParams& params) {
    const bool colour = params.outputColor.iterations > 0;
    const int total =
        colour + (params.outputDepth.iterations > 0 ? std::max(params.outputDepthRounds, 0) : 0);
    for (int i = 0; i < total; ++i) {
        const SmootherPass& pass = colour && i == 0 ? params.outputColor : params.outputDepth;
        if (i + 1 < total)
            runPass(output, pass);
        else
            smoothPass(output, pass);
    }
    resultPending = total > 0;
}

namespace {

// The minimum and maximum of each column's measured depths (> 0) over rows a, b, c, at x + 1 for column x;
// the row's end columns are repeated once beyond it. A column with none has lo = FLT_MAX, hi = 0.
DC_VECTOR_KERNEL void columnRange(const float* __restrict a, const float* __restrict b,
                                  const float* __restrict c, float* __restrict lo, float* __restrict hi,
                                  int n) {
    for (int x = 0; x < n; ++x) {
        const float pa = a[x] > 0.0f ? a[x] : FLT_MAX, pb = b[x] > 0.0f ? b[x] : FLT_MAX,
                    pc = c[x] > 0.0f ? c[x] : FLT_MAX;
        lo[x + 1] = std::min(std::min(pa, pb), pc);
        hi[x + 1] = std::max(std::max(std::max(a[x], b[x]), c[x]), 0.0f);
    }
    for (float* p : {lo, hi}) {
        p[0] = p[1];
        p[n + 1] = p[n];
    }
}

// Each measured pixel of `row` whose 3 x 3 range exceeds `range` to the nearer end of it (kept at a tie).
DC_VECTOR_KERNEL void snapRow(const float* __restrict lo, const float* __restrict hi,
                              const float* __restrict row, float* __restrict out, float range, int n) {
    for (int x = 0; x < n; ++x) {
        const float low = std::min(std::min(lo[x], lo[x + 1]), lo[x + 2]);
        const float high = std::max(std::max(hi[x], hi[x + 1]), hi[x + 2]);
        const float v = row[x], below = v - low, above = high - v;
        const float snapped = below < above ? low : above < below ? high : v;
        out[x] = v > 0.0f && high - low > range ? snapped : v;
    }
}

} // namespace

void GlobalSmoother::Buffers::snapEdges(float range, frame::DepthData& out) {
    const int width = out.depthMeters.width, last = out.depthMeters.height - 1;
    unsnapped = out.depthMeters.pixels;
    const std::size_t n = static_cast<std::size_t>(width) + 2;
    rowsInParallel(last + 1, [&](int y) {
        thread_local std::vector<float> scratch;
        scratch.resize(2 * n);
        const auto row = [&](int r) {
            return unsnapped.data() + static_cast<std::size_t>(std::clamp(r, 0, last)) * width;
        };
        columnRange(row(y - 1), row(y), row(y + 1), scratch.data(), scratch.data() + n, width);
        snapRow(scratch.data(), scratch.data() + n, row(y),
                out.depthMeters.pixels.data() + static_cast<std::size_t>(y) * width, range, width);
    });
}

GlobalSmoother::GlobalSmoother() : buffers_(std::make_unique<Buffers>()) {}
GlobalSmoother::~GlobalSmoother() = default;
GlobalSmoother::GlobalSmoother(GlobalSmoother&&) noexcept = default;
GlobalSmoother& GlobalSmoother::operator=(GlobalSmoother&&) noexcept = default;

frame::DepthData GlobalSmoother::upsample(const frame::DepthData& depth, ColorView guide,
                                          const GlobalSmootherParams& params) {
    if (guide.empty() || depth.depthMeters.empty())
        return depth;
    Buffers& b = *buffers_;
    const int width = guide.width, height = guide.height;
    frame::DepthData out{frame::Plane<float>(width, height), {}, depth.confidenceEstimated};
    if (!depth.confidence.empty() && depth.confidence.pixels.size() == depth.depthMeters.pixels.size()) {
        out.confidence = frame::Plane<std::uint8_t>(width, height);
        cv::resize(asMat(depth.confidence), asMat(out.confidence), {width, height}, 0, 0, cv::INTER_LINEAR);
    }
    if (!b.prepareSensor(depth))
        return out;
    resize(b.output, width, height);
    b.reduceGuide(guide);
    dataAsValue(b.sensor);
    runPass(b.sensor, params.sensorColor);
    for (int round = 0; round < params.sensorDepthRounds; ++round)
        runPass(b.sensor, params.sensorDepth);
    b.upsampleSensor(params.footprintSigma);
    b.runOutputPasses(params);
    b.finish(params, guide, out);
    if (params.edgeSnapRange > 0.0f)
        b.snapEdges(params.edgeSnapRange, out);
    return out;
}

} // namespace dc::processing
