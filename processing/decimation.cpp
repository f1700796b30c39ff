#include "processing/decimation.h"

#include "processing/confidence_filter.h"
#include "processing/parallel.h"

#include <algorithm>
#include <limits>

namespace dc::processing {

namespace {

int cells(int size, int factor) {
    return (size + factor - 1) / factor;
}

} // namespace

int footprintFactor(int width, int height, std::size_t maxPoints) {
    if (maxPoints == 0 || width <= 0 || height <= 0)
        return 1;
    int factor = 1;
    while (static_cast<std::size_t>(cells(width, factor)) * static_cast<std::size_t>(cells(height, factor)) >
           maxPoints)
        ++factor;
    return factor;
}

DecimatedDepth decimateNearest(const frame::DepthData& depth, const frame::Intrinsics& intrinsics, int factor,
                               frame::Confidence minLevel, float nearMeters) {
    const int width = depth.depthMeters.width;
    const int height = depth.depthMeters.height;
    const int outWidth = cells(width, factor);
    const int outHeight = cells(height, factor);
    const bool hasConfidence = !depth.confidence.empty();
    auto out = std::make_shared<frame::DepthData>();
    out->depthMeters = frame::Plane<float>(outWidth, outHeight, 0.0f);
    out->confidence = frame::Plane<std::uint8_t>(outWidth, outHeight, 0);
    out->confidenceEstimated = depth.confidenceEstimated;
    constexpr auto kHigh = static_cast<std::uint8_t>(frame::Confidence::High);
    parallelRanges(outHeight, 8, [&](int begin, int end) {
        for (int cy = begin; cy < end; ++cy)
            for (int cx = 0; cx < outWidth; ++cx) {
                float nearest = std::numeric_limits<float>::infinity();
                std::size_t kept = 0;
                for (int y = cy * factor; y < std::min(height, (cy + 1) * factor); ++y)
                    for (int x = cx * factor; x < std::min(width, (cx + 1) * factor); ++x) {
                        const std::size_t i = static_cast<std::size_t>(y) * width + x;
                        const float z = depth.depthMeters.pixels[i];
                        const std::uint8_t c = hasConfidence ? depth.confidence.pixels[i] : kHigh;
                        if (keepSample(z, c, minLevel, nearMeters) && z < nearest) {
                            nearest = z;
                            kept = i;
                        }
                    }
                if (nearest == std::numeric_limits<float>::infinity())
                    continue;
                const std::size_t o = static_cast<std::size_t>(cy) * outWidth + cx;
                out->depthMeters.pixels[o] = nearest;
                out->confidence.pixels[o] = hasConfidence ? depth.confidence.pixels[kept] : kHigh;
            }
    });
    frame::Intrinsics k = intrinsics;
    const double f = factor;
    // Cell (c) spans samples [f c, f c + f): its centre is sample f c + (f - 1) / 2.
    k.fx /= f;
    k.fy /= f;
    k.cx = (k.cx - (f - 1.0) / 2.0) / f;
    k.cy = (k.cy - (f - 1.0) / 2.0) / f;
    k.width = outWidth;
    k.height = outHeight;
    return {std::move(out), k};
}

namespace {

template <class T> frame::Plane<T> cellCentres(const frame::Plane<T>& plane, int step) {
    if (plane.empty())
        return {};
    frame::Plane<T> out(cells(plane.width, step), cells(plane.height, step));
    for (int cy = 0; cy < out.height; ++cy) {
        const int y = std::min(plane.height - 1, cy * step + step / 2);
        for (int cx = 0; cx < out.width; ++cx)
            out.at(cx, cy) = plane.at(std::min(plane.width - 1, cx * step + step / 2), y);
    }
    return out;
}

} // namespace

frame::DepthData sampleCellCentres(const frame::DepthData& depth, int step) {
    frame::DepthData out;
    out.depthMeters = cellCentres(depth.depthMeters, step);
    out.confidence = cellCentres(depth.confidence, step);
    out.confidenceEstimated = depth.confidenceEstimated;
    return out;
}

int panelSampleStep(int mapWidth, int shownWidth) {
    return shownWidth > 0 ? std::max(1, mapWidth / shownWidth) : 1;
}

} // namespace dc::processing
