#include "render/cloud_splat.h"

#include "processing/confidence_filter.h"
#include "processing/parallel.h"
#include "render/point_cloud_renderer.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>

namespace dc::render {

namespace {

// Pieces of the sources and bands of the image: a few per core, so a core another process delays does
// not hold up the frame.
constexpr int kPieces = 8;
constexpr int kBands = 8;
constexpr std::uint32_t kMidGray = 0x808080; // FrameTextures' colour for samples without one

std::uint32_t packRgb(float r, float g, float b) {
    const auto unorm = [](float v) {
        return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    };
    return unorm(r) | unorm(g) << 8 | unorm(b) << 16;
}

std::uint32_t confidenceRgb(std::uint8_t level) {
    return level == 0 ? 0x0000ffu : level == 1 ? 0x00ff00u : level == 2 ? 0xff0000u : 0u;
}

constexpr std::uint32_t kOpaque = 0xff000000u;

} // namespace

bool CloudSplatter::makesPicture(const CloudParams& params) {
    return params.anchors.empty();
}

// Points in clip space, a coordinate per array, so that placing them vectorises. A point whose w is 0
// lands nowhere (samples that are not drawn are written so rather than skipped, keeping the loops straight).
struct CloudSplatter::ClipBatch {
    std::vector<float> x, y, z, w, fill;

    void resize(std::size_t n) {
        for (auto* axis : {&x, &y, &z, &w, &fill})
            axis->resize(n);
    }
};

// Where each point of a batch lands: its first covered pixel, its size (0 outside the clip volume) and
// its window depth's bits.
struct CloudSplatter::Placed {
    std::vector<int> x, y, size;
    std::vector<std::uint32_t> depthBits;

    void resize(std::size_t n) {
        for (auto* v : {&x, &y, &size})
            v->resize(n);
        depthBits.resize(n);
    }
};

namespace {

// floor-free ceil through one truncating conversion: x86-64's baseline (SSE2) has no rounding
// instruction, and std::ceil would keep the loop scalar.
int ceilOf(float v) {
    const auto i = static_cast<int>(v);
    return i + static_cast<int>(v > static_cast<float>(i));
}

} // namespace

// Window coordinates as GL computes them; the point covers the pixels whose centres fall in the
// size x size square around it, at least pointSize wide and as wide as `fill` (the sample's footprint,
// pixels, when gaps are filled) rounded up. Every lane is computed and those outside the clip volume
// are given size 0, without a branch.
void CloudSplatter::place(const ClipBatch& c, std::size_t n, int pointSize, Placed& out) const {
    const float width = static_cast<float>(width_);
    const float height = static_cast<float>(height_);
    for (std::size_t i = 0; i < n; ++i) {
        const float w = c.w[i];
        const bool inside =
            (w > 0.0f) & (std::abs(c.x[i]) <= w) & (std::abs(c.y[i]) <= w) & (std::abs(c.z[i]) <= w);
        const float inverseW = 1.0f / w;
        const float footprint = c.fill[i] * inverseW;
        // Clamped before the conversion, NaN included, so that it stays in range on every lane.
        const float wide =
            footprint < kMaxFillPixels ? (footprint > 0.0f ? footprint : 0.0f) : kMaxFillPixels;
        const int size = std::max(pointSize, ceilOf(wide));
        const float offset = 0.5f * static_cast<float>(size) + 0.5f;
        const float xw = (c.x[i] * inverseW * 0.5f + 0.5f) * width;
        const float yw = (c.y[i] * inverseW * 0.5f + 0.5f) * height;
        out.x[i] = ceilOf(inside ? xw - offset : 0.0f);
        out.y[i] = ceilOf(inside ? yw - offset : 0.0f);
        out.size[i] = inside ? size : 0;
        out.depthBits[i] = std::bit_cast<std::uint32_t>(c.z[i] * inverseW * 0.5f + 0.5f);
    }
}

template <class Project>
void CloudSplatter::run(int sourceRows, const CloudParams& params, int width, int height, Project&& project) {
    width_ = std::max(width, 0);
    height_ = std::max(height, 0);
    keys_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
    const bool picture = makesPicture(params);
    picture_.resize(picture ? keys_.size() : 0);
    // RGBA of the picture where no point landed.
    const std::uint32_t background =
        packRgb(params.background.r, params.background.g, params.background.b) | kOpaque;
    splats_.resize(kPieces);
    for (auto& bands : splats_) {
        bands.resize(kBands);
        for (auto& splats : bands)
            splats.clear();
    }
    const int pointSize = std::max(1, static_cast<int>(std::lround(params.pointSizePixels)));
    const int bandRows = std::max(1, (height_ + kBands - 1) / kBands);
    // The band of each row a splat may reach (it may start up to a splat's size above the image): a
    // lookup, where a division per point costs more than the rest of placing it.
    const int firstRow = -static_cast<int>(kMaxFillPixels) - pointSize;
    std::vector<std::uint8_t> bandOfRow(static_cast<std::size_t>(height_ - firstRow + 1));
    for (std::size_t r = 0; r < bandOfRow.size(); ++r)
        bandOfRow[r] =
            static_cast<std::uint8_t>(std::clamp((static_cast<int>(r) + firstRow) / bandRows, 0, kBands - 1));
    const auto bandOf = [&](int row) {
        return bandOfRow[static_cast<std::size_t>(std::clamp(row, firstRow, height_) - firstRow)];
    };
    std::atomic<std::size_t> projected{0};
    processing::parallelRanges(kPieces, 1, [&](int first, int last) {
        Placed placed;
        for (int piece = first; piece < last; ++piece) {
            auto& bands = splats_[static_cast<std::size_t>(piece)];
            std::size_t count = 0;
            const auto emit = [&](const ClipBatch& batch, std::size_t n, std::size_t kept,
                                  const auto& rgbOf) {
                count += kept;
                placed.resize(n);
                place(batch, n, pointSize, placed);
                for (std::size_t i = 0; i < n; ++i) {
                    const int size = placed.size[i];
                    if (size == 0)
                        continue;
                    const Splat splat{static_cast<std::int16_t>(placed.x[i]),
                                      static_cast<std::int16_t>(placed.y[i]),
                                      static_cast<std::uint16_t>(size),
                                      std::uint64_t{placed.depthBits[i]} << 32 | rgbOf(i)};
                    const int lastBand = bandOf(splat.y + size - 1);
                    for (int band = bandOf(splat.y); band <= lastBand; ++band)
                        bands[static_cast<std::size_t>(band)].push_back(splat);
                }
            };
            project(sourceRows * piece / kPieces, sourceRows * (piece + 1) / kPieces, emit);
            projected += count;
        }
    });
    pointCount_ = projected;
    processing::parallelRanges(kBands, 1, [&](int first, int last) {
        for (int band = first; band < last; ++band) {
            write(band, bandRows);
            if (picture)
                paint(band, bandRows, background); // while the band's keys are still in this core's cache
        }
    });
}

void CloudSplatter::write(int band, int bandRows) {
    const int top = std::min(height_, band * bandRows);
    const int bottom = std::min(height_, (band + 1) * bandRows);
    std::uint64_t* keys = keys_.data();
    std::fill(keys + static_cast<std::size_t>(top) * width_, keys + static_cast<std::size_t>(bottom) * width_,
              kEmpty);
    for (const auto& pieces : splats_)
        for (const Splat& s : pieces[static_cast<std::size_t>(band)]) {
            const int x0 = std::max<int>(s.x, 0);
            const int x1 = std::min(s.x + s.size, width_);
            for (int y = std::max<int>(s.y, top); y < std::min(s.y + s.size, bottom); ++y) {
                std::uint64_t* row = keys + static_cast<std::size_t>(y) * width_;
                for (int x = x0; x < x1; ++x)
                    row[x] = std::min(row[x], s.key);
            }
        }
}

void CloudSplatter::paint(int band, int bandRows, std::uint32_t background) {
    const std::size_t first = static_cast<std::size_t>(std::min(height_, band * bandRows)) * width_;
    const std::size_t end = static_cast<std::size_t>(std::min(height_, (band + 1) * bandRows)) * width_;
    for (std::size_t i = first; i < end; ++i)
        picture_[i] = keys_[i] == kEmpty ? background : static_cast<std::uint32_t>(keys_[i]) | kOpaque;
}

// Which samples the cloud draws, as processing::keepSample decides.
struct CloudSplatter::SampleFilter {
    frame::Confidence minConfidence;
    float nearMeters;
};

namespace {

// out = z * (column + r) + t, lane by lane: one coordinate of a row of samples in clip space. A loop of
// its own over three arrays, where one loop over them all needs more run-time overlap checks than the
// vectoriser makes.
void clipAxis(const float* z, const float* column, float r, float t, std::size_t n, float* out) {
    for (std::size_t u = 0; u < n; ++u)
        out[u] = z[u] * (column[u] + r) + t;
}

} // namespace

// One row of samples in clip space: each column's ray through the view-projection (x, y, z and w
// arrays) plus the row's, scaled by the depth, plus the translation; what is not drawn gets w = 0.
std::size_t CloudSplatter::projectRow(const float* z, const std::uint8_t* levels,
                                      const std::array<std::vector<float>, 4>& columns, glm::vec4 row,
                                      glm::vec4 translation, SampleFilter filter, float footprint,
                                      ClipBatch& batch) {
    const std::size_t n = batch.x.size();
    clipAxis(z, columns[0].data(), row.x, translation.x, n, batch.x.data());
    clipAxis(z, columns[1].data(), row.y, translation.y, n, batch.y.data());
    clipAxis(z, columns[2].data(), row.z, translation.z, n, batch.z.data());
    clipAxis(z, columns[3].data(), row.w, translation.w, n, batch.w.data());
    float* w = batch.w.data();
    float* fill = batch.fill.data();
    unsigned kept = 0;
    for (std::size_t u = 0; u < n; ++u) {
        const bool keep = processing::keepSample(z[u], levels[u], filter.minConfidence, filter.nearMeters);
        kept += keep ? 1u : 0u;
        w[u] = keep ? w[u] : 0.0f;
        fill[u] = z[u] * footprint;
    }
    return kept;
}

void CloudSplatter::splatSamples(const frame::DepthData& depth, const frame::Intrinsics& k,
                                 const processing::RgbImage* colours, const CloudParams& params, int width,
                                 int height) {
    const SplatSource one{&depth, k, colours, params.viewProjection, std::nullopt, std::nullopt};
    splatSources({&one, 1}, params, width, height);
}

// A source's samples made ready to project: each column's ray through its view-projection, and where its
// rows start among all the sources' rows.
struct CloudSplatter::PreparedSource {
    const SplatSource* source = nullptr;
    int width = 0;
    int height = 0;
    int firstRow = 0;
    bool hasColours = false;
    bool hasConfidence = false;
    float footprint = 0.0f;
    std::array<std::vector<float>, 4> columns; // x, y, z, w of each column's ray through the matrix
};

std::vector<CloudSplatter::PreparedSource> CloudSplatter::prepare(std::span<const SplatSource> sources,
                                                                  const CloudParams& params, int width,
                                                                  int height) const {
    std::vector<PreparedSource> prepared;
    int rows = 0;
    for (const SplatSource& s : sources) {
        if (!s.depth || !s.intrinsics.valid())
            continue;
        PreparedSource p;
        p.source = &s;
        p.width = s.depth->depthMeters.width;
        p.height = s.depth->depthMeters.height;
        p.firstRow = rows;
        rows += p.height;
        p.hasColours = s.colours && s.colours->width == p.width && s.colours->height == p.height;
        p.hasConfidence = !s.depth->confidence.empty();
        p.footprint = footprintPixelsPerDepth(params, s.intrinsics, width, height);
        for (auto& axis : p.columns)
            axis.resize(static_cast<std::size_t>(p.width));
        for (int u = 0; u < p.width; ++u) {
            const glm::vec4 c =
                static_cast<float>((u - s.intrinsics.cx) / s.intrinsics.fx) * s.viewProjection[0];
            for (int a = 0; a < 4; ++a)
                p.columns[static_cast<std::size_t>(a)][static_cast<std::size_t>(u)] = c[a];
        }
        prepared.push_back(std::move(p));
    }
    return prepared;
}

void CloudSplatter::splatSources(std::span<const SplatSource> sources, const CloudParams& params, int width,
                                 int height) {
    if (params.coloring == PointColoring::Depth)
        for (std::size_t i = 0; i < colormapTable_.size(); ++i) {
            const auto c =
                colormapColor(params.colormap, static_cast<float>(i) / (colormapTable_.size() - 1));
            colormapTable_[i] = packRgb(c[0], c[1], c[2]);
        }
    const float rangeMin = params.rangeMinMeters;
    const float inverseRange = 1.0f / std::max(params.rangeMaxMeters - params.rangeMinMeters, 1e-6f);
    const auto colorOf = [&](const PreparedSource& p, std::size_t i, float z,
                             std::uint8_t level) -> std::uint32_t {
        if (p.source->tint)
            return *p.source->tint;
        switch (params.coloring) {
        case PointColoring::Camera: {
            const std::uint8_t* rgb = p.hasColours ? &p.source->colours->pixels[i * 3] : nullptr;
            return rgb ? rgb[0] | rgb[1] << 8 | static_cast<std::uint32_t>(rgb[2]) << 16 : kMidGray;
        }
        case PointColoring::Depth: {
            const float n = (z - rangeMin) * inverseRange;
            const float clamped = n > 0.0f ? std::min(n, 1.0f) : 0.0f;
            return colormapTable_[static_cast<std::size_t>(clamped * (colormapTable_.size() - 1) + 0.5f)];
        }
        case PointColoring::Confidence:
            return confidenceRgb(level);
        }
        return kMidGray;
    };
    const std::vector<PreparedSource> prepared = prepare(sources, params, width, height);
    const int rows = prepared.empty() ? 0 : prepared.back().firstRow + prepared.back().height;
    int widest = 0;
    for (const PreparedSource& p : prepared)
        widest = std::max(widest, p.width);
    run(rows, params, width, height, [&](int firstRow, int lastRow, const auto& emit) {
        ClipBatch batch;
        // Without a confidence map every sample counts as high.
        const std::vector<std::uint8_t> allHigh(static_cast<std::size_t>(widest), 2);
        std::size_t s = 0;
        for (int r = firstRow; r < lastRow; ++r) {
            while (r >= prepared[s].firstRow + prepared[s].height)
                ++s;
            const PreparedSource& p = prepared[s];
            const frame::Intrinsics& k = p.source->intrinsics;
            const glm::mat4& m = p.source->viewProjection;
            const int v = r - p.firstRow;
            batch.resize(static_cast<std::size_t>(p.width));
            const glm::vec4 row = static_cast<float>((v - k.cy) / k.fy) * m[1] + m[2];
            const std::size_t first = static_cast<std::size_t>(v) * static_cast<std::size_t>(p.width);
            const float* z = &p.source->depth->depthMeters.pixels[first];
            const std::uint8_t* levels =
                p.hasConfidence ? &p.source->depth->confidence.pixels[first] : allHigh.data();
            const SampleFilter keep{p.source->minConfidence.value_or(params.minConfidence),
                                    params.nearMeters};
            const std::size_t kept = projectRow(z, levels, p.columns, row, m[3], keep, p.footprint, batch);
            emit(batch, static_cast<std::size_t>(p.width), kept,
                 [&](std::size_t u) { return colorOf(p, first + u, z[u], levels[u]); });
        }
    });
}

void CloudSplatter::splatWorld(const std::vector<processing::WorldPoint>& points, std::size_t count,
                               const CloudParams& params, int width, int height) {
    constexpr int kPerRow = 4096;
    count = std::min(count, points.size());
    const int rows = static_cast<int>((count + kPerRow - 1) / kPerRow);
    const glm::mat4& m = params.worldToClip;
    run(rows, params, width, height, [&](int firstRow, int lastRow, const auto& emit) {
        ClipBatch batch;
        batch.resize(kPerRow);
        for (int r = firstRow; r < lastRow; ++r) {
            const std::size_t first = static_cast<std::size_t>(r) * kPerRow;
            const std::size_t n = std::min(count, first + kPerRow) - first;
            for (std::size_t i = 0; i < n; ++i) {
                const processing::WorldPoint& p = points[first + i];
                const glm::vec4 clip = m * glm::vec4(p.x, p.y, p.z, 1.0f);
                batch.x[i] = clip.x;
                batch.y[i] = clip.y;
                batch.z[i] = clip.z;
                batch.w[i] = clip.w;
                batch.fill[i] = 0.0f;
            }
            emit(batch, n, n, [&](std::size_t i) { return points[first + i].rgba & 0xffffffu; });
        }
    });
}

} // namespace dc::render
