#include "processing/quality_maps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace dc::processing {

namespace {

// The range's end: the 98th percentile, so that a few wild pixels do not wash out the rest of the map.
constexpr double kRangePercentile = 0.98;

using Rgb = std::array<float, 3>;

// Dark blue, teal, green, yellow: ordered in lightness, readable in grey too.
constexpr std::array<Rgb, 4> kSequential{
    {{0.18f, 0.0f, 0.45f}, {0.12f, 0.45f, 0.55f}, {0.30f, 0.75f, 0.35f}, {0.99f, 0.91f, 0.15f}}};
// Blue, white at the middle (on the plane), red.
constexpr std::array<Rgb, 3> kDiverging{
    {{0.15f, 0.30f, 0.85f}, {0.97f, 0.97f, 0.97f}, {0.85f, 0.15f, 0.15f}}};

template <std::size_t N> std::array<std::uint8_t, 3> ramp(const std::array<Rgb, N>& stops, float t) {
    const float at = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * static_cast<float>(N - 1);
    const auto i = std::min(static_cast<std::size_t>(at), N - 2);
    const float f = at - static_cast<float>(i);
    std::array<std::uint8_t, 3> rgb{};
    for (std::size_t c = 0; c < 3; ++c)
        rgb[c] = static_cast<std::uint8_t>(
            std::lround(255.0f * (stops[i][c] + f * (stops[i + 1][c] - stops[i][c]))));
    return rgb;
}

// The kRangePercentile-th of the finite values' magnitudes; none when there is no finite value.
std::optional<float> upperMagnitude(const frame::Plane<float>& values) {
    std::vector<float> magnitudes;
    magnitudes.reserve(values.pixels.size());
    for (const float v : values.pixels)
        if (std::isfinite(v))
            magnitudes.push_back(std::abs(v));
    if (magnitudes.empty())
        return std::nullopt;
    const auto at = static_cast<std::size_t>(kRangePercentile * static_cast<double>(magnitudes.size() - 1));
    std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<std::ptrdiff_t>(at),
                     magnitudes.end());
    return magnitudes[at];
}

} // namespace

const char* toString(QualityMap map) {
    switch (map) {
    case QualityMap::None:
        return "none";
    case QualityMap::PlaneResidual:
        return "plane residual";
    case QualityMap::TemporalStd:
        return "temporal deviation";
    case QualityMap::FillOverWindow:
        return "fill over the window";
    }
    return "none";
}

const char* unitOf(QualityMap map) {
    return map == QualityMap::FillOverWindow ? "%" : "mm";
}

frame::Plane<float> planeResidualMm(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                    const Roi& roi, std::span<const SampleCause> causes,
                                    const PlaneModel& plane) {
    frame::Plane<float> map(roi.width, roi.height, std::numeric_limits<float>::quiet_NaN());
    if (causes.size() != map.pixels.size() ||
        !roiInside(roi, depth.depthMeters.width, depth.depthMeters.height))
        return map;
    std::size_t i = 0;
    for (int y = roi.y; y < roi.y + roi.height; ++y) {
        for (int x = roi.x; x < roi.x + roi.width; ++x, ++i) {
            if (causes[i] != SampleCause::Valid)
                continue;
            const double z = depth.depthMeters.at(x, y);
            const Point3d p{(x - intrinsics.cx) * z / intrinsics.fx, (y - intrinsics.cy) * z / intrinsics.fy,
                            z};
            map.pixels[i] = static_cast<float>(plane.signedDistance(p) * kMetersToMm);
        }
    }
    return map;
}

std::array<std::uint8_t, 3> mapColour(QualityMap kind, float t) {
    return kind == QualityMap::PlaneResidual ? ramp(kDiverging, t) : ramp(kSequential, t);
}

QualityMapImage colourMap(QualityMap kind, frame::Plane<float> values) {
    QualityMapImage out;
    out.kind = kind;
    out.low = 0.0f;
    out.high = 1.0f;
    if (kind == QualityMap::FillOverWindow) {
        out.high = 100.0f;
    } else if (const auto upper = upperMagnitude(values); upper && *upper > 0.0f) {
        out.high = *upper;
        if (kind == QualityMap::PlaneResidual)
            out.low = -*upper;
    }
    out.image.width = values.width;
    out.image.height = values.height;
    out.image.pixels.assign(values.pixels.size() * 4, 0);
    const float span = out.high - out.low;
    for (std::size_t i = 0; i < values.pixels.size(); ++i) {
        const float v = values.pixels[i];
        if (!std::isfinite(v))
            continue;
        const auto rgb = mapColour(kind, (v - out.low) / span);
        std::copy(rgb.begin(), rgb.end(), out.image.pixels.begin() + static_cast<std::ptrdiff_t>(i * 4));
        out.image.pixels[i * 4 + 3] = 255;
    }
    out.values = std::move(values);
    return out;
}

} // namespace dc::processing
