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
    std::atomic<std::size_t> projected{0};
    processing::parallelRanges(kPieces, 1, [&](int first, int last) {
        for (int piece = first; piece < last; ++piece) {
            auto& bands = splats_[static_cast<std::size_t>(piece)];
            std::size_t count = 0;
            // Window coordinates as GL computes them; the point covers the pixels whose centres fall in
            // the size x size square around it, at least pointSize wide and as wide as `fill` (the sample's
            // footprint, pixels, when gaps are filled) rounded up.
            const auto emit = [&](const glm::vec4& clip, std::uint32_t rgb, float fill) {
                ++count;
                if (!(clip.w > 0.0f) || std::abs(clip.x) > clip.w || std::abs(clip.y) > clip.w ||
                    std::abs(clip.z) > clip.w)
                    return;
                const float inverseW = 1.0f / clip.w;
                const int size = std::max(
                    pointSize, static_cast<int>(std::min(std::ceil(fill * inverseW), kMaxFillPixels)));
                const float offset = 0.5f * static_cast<float>(size) + 0.5f;
                const float xw = (clip.x * inverseW * 0.5f + 0.5f) * static_cast<float>(width_);
                const float yw = (clip.y * inverseW * 0.5f + 0.5f) * static_cast<float>(height_);
                const float zw = clip.z * inverseW * 0.5f + 0.5f;
                const Splat splat{static_cast<std::int16_t>(std::ceil(xw - offset)),
                                  static_cast<std::int16_t>(std::ceil(yw - offset)),
                                  static_cast<std::uint16_t>(size),
                                  std::uint64_t{std::bit_cast<std::uint32_t>(zw)} << 32 | rgb};
                const int firstBand = std::clamp(splat.y / bandRows, 0, kBands - 1);
                const int lastBand = std::clamp((splat.y + size - 1) / bandRows, 0, kBands - 1);
                for (int band = firstBand; band <= lastBand; ++band)
                    bands[static_cast<std::size_t>(band)].push_back(splat);
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

void CloudSplatter::splatSamples(const frame::DepthData& depth, const frame::Intrinsics& k,
                                 const processing::RgbImage* colors, const CloudParams& params, int width,
                                 int height) {
    const int w = depth.depthMeters.width;
    const int h = depth.depthMeters.height;
    const bool hasColors = colors && colors->width == w && colors->height == h;
    const bool hasConfidence = !depth.confidence.empty();
    if (params.coloring == PointColoring::Depth)
        for (std::size_t i = 0; i < colormapTable_.size(); ++i) {
            const auto c =
                colormapColor(params.colormap, static_cast<float>(i) / (colormapTable_.size() - 1));
            colormapTable_[i] = packRgb(c[0], c[1], c[2]);
        }
    const float rangeMin = params.rangeMinMeters;
    const float inverseRange = 1.0f / std::max(params.rangeMaxMeters - params.rangeMinMeters, 1e-6f);
    const glm::mat4& m = params.viewProjection;
    const float footprint = footprintPixelsPerDepth(params, k, width, height);
    std::vector<glm::vec4> columns(static_cast<std::size_t>(w));
    for (int u = 0; u < w; ++u)
        columns[static_cast<std::size_t>(u)] = static_cast<float>((u - k.cx) / k.fx) * m[0];
    const auto colorOf = [&](std::size_t i, float z, std::uint8_t level) -> std::uint32_t {
        switch (params.coloring) {
        case PointColoring::Camera:
            return hasColors ? colors->pixels[i * 3] | colors->pixels[i * 3 + 1] << 8 |
                                   static_cast<std::uint32_t>(colors->pixels[i * 3 + 2]) << 16
                             : kMidGray;
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
    run(h, params, width, height, [&](int firstRow, int lastRow, const auto& emit) {
        for (int v = firstRow; v < lastRow; ++v) {
            const glm::vec4 row = static_cast<float>((v - k.cy) / k.fy) * m[1] + m[2];
            for (int u = 0; u < w; ++u) {
                const std::size_t i = static_cast<std::size_t>(v) * w + u;
                const float z = depth.depthMeters.pixels[i];
                const std::uint8_t level = hasConfidence ? depth.confidence.pixels[i] : 2;
                if (processing::keepSample(z, level, params.minConfidence, params.nearMeters))
                    emit(z * (columns[static_cast<std::size_t>(u)] + row) + m[3], colorOf(i, z, level),
                         z * footprint);
            }
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
        const std::size_t end = std::min(count, static_cast<std::size_t>(lastRow) * kPerRow);
        for (std::size_t i = static_cast<std::size_t>(firstRow) * kPerRow; i < end; ++i) {
            const processing::WorldPoint& p = points[i];
            emit(m * glm::vec4(p.x, p.y, p.z, 1.0f), p.rgba & 0xffffffu, 0.0f);
        }
    });
}

} // namespace dc::render
