#include "processing/point_cloud.h"

#include "frame/color.h"
#include "processing/confidence_filter.h"
#include "processing/point_colours.h"
#include "processing/registration.h"

#include <algorithm>
#include <cstdlib>

namespace dc::processing {

namespace {

// Pixels of `roi`'s border from its top-left corner around to the pixel before it, every corner among
// them and each side cut into segments of at most `step` pixels. A one-pixel-wide region's border goes
// along it and back; a one-pixel region's is that pixel.
std::vector<std::array<int, 2>> borderPixels(const Roi& roi, int step) {
    const int x0 = roi.x, y0 = roi.y, x1 = roi.x + roi.width - 1, y1 = roi.y + roi.height - 1;
    const std::array<std::array<int, 2>, 5> corners{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}};
    std::vector<std::array<int, 2>> pixels;
    for (std::size_t side = 0; side < 4; ++side) {
        const auto [ax, ay] = corners[side];
        const auto [bx, by] = corners[side + 1];
        const int length = std::abs(bx - ax) + std::abs(by - ay);
        const int segments = (length + step - 1) / step;
        // i < segments: the side's end is the next side's start.
        for (int i = 0; i < segments; ++i)
            pixels.push_back({ax + (bx - ax) * i / segments, ay + (by - ay) * i / segments});
    }
    if (pixels.empty())
        pixels.push_back(corners[0]);
    return pixels;
}

// The pixels a polygon's edges pass through, a step of at most one pixel along each edge, then every n-th
// of them so that there are at most `most`.
std::vector<std::array<int, 2>> polygonPixels(const Polygon& polygon, int width, int height, int most) {
    std::vector<std::array<int, 2>> pixels;
    const auto pixelAt = [&](double x, double y) {
        return std::array<int, 2>{std::clamp(static_cast<int>(std::floor(x)), 0, width - 1),
                                  std::clamp(static_cast<int>(std::floor(y)), 0, height - 1)};
    };
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const auto& a = polygon[i];
        const auto& b = polygon[(i + 1) % polygon.size()];
        const double length = std::max(std::abs(b[0] - a[0]), std::abs(b[1] - a[1]));
        const int steps = std::max(1, static_cast<int>(std::ceil(length)));
        for (int s = 0; s < steps; ++s) {
            const double t = static_cast<double>(s) / steps;
            const auto p = pixelAt(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
            if (pixels.empty() || pixels.back() != p)
                pixels.push_back(p);
        }
    }
    const std::size_t step =
        (pixels.size() + static_cast<std::size_t>(most) - 1) / static_cast<std::size_t>(most);
    if (step <= 1)
        return pixels;
    std::vector<std::array<int, 2>> kept;
    for (std::size_t i = 0; i < pixels.size(); i += step)
        kept.push_back(pixels[i]);
    return kept;
}

// The outline through `pixels` (a closed walk) on the surface, as roiOutline describes it.
std::vector<Polyline3> outlineThrough(const std::vector<std::array<int, 2>>& pixels,
                                      const frame::DepthData& depth, const frame::Intrinsics& k,
                                      frame::Confidence minLevel, float nearMeters) {
    const frame::Plane<float>& d = depth.depthMeters;
    const auto drawn = [&](const std::array<int, 2>& p) {
        const std::uint8_t c = depth.confidence.empty() ? 2 : depth.confidence.at(p[0], p[1]);
        return keepSample(d.at(p[0], p[1]), c, minLevel, nearMeters);
    };
    const auto place = [&](const std::array<int, 2>& p) {
        return unproject(p[0], p[1], d.at(p[0], p[1]), k);
    };
    const auto gap = std::find_if_not(pixels.begin(), pixels.end(), drawn);
    if (gap == pixels.end()) {
        Polyline3 closed;
        for (const auto& p : pixels)
            closed.push_back(place(p));
        closed.push_back(closed.front());
        return {closed};
    }
    // Walked from a gap round to it again, no run is cut in two where the walk began.
    std::vector<Polyline3> runs;
    Polyline3 run;
    const std::size_t start = static_cast<std::size_t>(gap - pixels.begin());
    for (std::size_t i = 1; i <= pixels.size(); ++i) {
        const auto& p = pixels[(start + i) % pixels.size()];
        if (drawn(p)) {
            run.push_back(place(p));
            continue;
        }
        if (run.size() >= 2)
            runs.push_back(run);
        run.clear();
    }
    return runs;
}

} // namespace

bool CloudSamples::usable() const {
    if (!depth || !intrinsics.valid())
        return false;
    const auto& d = depth->depthMeters;
    return d.width > 0 && d.height > 0 && d.pixels.size() == static_cast<std::size_t>(d.width) * d.height &&
           (!colours || (colours->width == d.width && colours->height == d.height));
}

std::vector<CloudPoint> buildPointCloud(const CloudSamples& samples, frame::Confidence minLevel,
                                        float nearMeters) {
    std::vector<CloudPoint> points;
    if (!samples.usable())
        return points;
    const frame::DepthData& depth = *samples.depth;
    const int w = depth.depthMeters.width, h = depth.depthMeters.height;
    const std::uint8_t gray = frame::toByte(0.5f);
    points.reserve(depth.depthMeters.pixels.size());
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const float z = depth.depthMeters.at(u, v);
            const std::uint8_t c = depth.confidence.empty() ? 2 : depth.confidence.at(u, v);
            if (!keepSample(z, c, minLevel, nearMeters))
                continue;
            const auto [x, y, zz] = unproject(u, v, z, samples.intrinsics);
            const std::uint8_t* rgb =
                samples.colours ? &samples.colours->pixels[(static_cast<std::size_t>(v) * w + u) * 3]
                                : nullptr;
            points.push_back({x, y, zz, rgb ? rgb[0] : gray, rgb ? rgb[1] : gray, rgb ? rgb[2] : gray, c});
        }
    }
    return points;
}

std::vector<CloudPoint> buildPointCloud(const frame::Frame& frame, frame::Confidence minLevel,
                                        float nearMeters) {
    if (!frame.sceneDepth)
        return {};
    const auto& d = frame.sceneDepth->depthMeters;
    CameraColourTable table;
    const PointColours colours = framePointColours(frame, d, table);
    return buildPointCloud({&*frame.sceneDepth, frame.depthIntrinsics(), colours.colours.get()}, minLevel,
                           nearMeters);
}

std::vector<Polyline3> roiOutline(const frame::DepthData& depth, const frame::Intrinsics& k, const Roi& roi,
                                  frame::Confidence minLevel, float nearMeters, int maxVertices) {
    const frame::Plane<float>& d = depth.depthMeters;
    if (!k.valid() || !roiInside(roi, d.width, d.height))
        return {};
    const int perimeter = 2 * (roi.width - 1) + 2 * (roi.height - 1);
    const int most = std::max(maxVertices, 1);
    const int step = std::max(1, (perimeter + most - 1) / most);
    return outlineThrough(borderPixels(roi, step), depth, k, minLevel, nearMeters);
}

std::vector<Polyline3> roiOutline(const frame::DepthData& depth, const frame::Intrinsics& k,
                                  const Polygon& polygon, frame::Confidence minLevel, float nearMeters,
                                  int maxVertices) {
    const frame::Plane<float>& d = depth.depthMeters;
    if (!k.valid() || polygon.size() < 3 || d.width <= 0 || d.height <= 0)
        return {};
    return outlineThrough(polygonPixels(polygon, d.width, d.height, std::max(maxVertices, 1)), depth, k,
                          minLevel, nearMeters);
}

} // namespace dc::processing
