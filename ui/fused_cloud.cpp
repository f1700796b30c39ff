#include "ui/fused_cloud.h"

#include "processing/point_cloud.h"
#include "render/colormap.h"

#include <algorithm>
#include <cmath>

namespace dc::ui {

namespace {

constexpr std::uint32_t kOpaque = 0xff000000u;

std::uint32_t pack(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return r | static_cast<std::uint32_t>(g) << 8 | static_cast<std::uint32_t>(b) << 16 | kOpaque;
}

std::uint32_t depthColour(const FusedLook& look, float z) {
    const float span = std::max(look.rangeMaxMeters - look.rangeMinMeters, 1e-6f);
    const auto c = render::colormapColor(look.colormap, (z - look.rangeMinMeters) / span);
    const auto unorm = [](float v) {
        return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.f, 1.f) * 255));
    };
    return pack(unorm(c[0]), unorm(c[1]), unorm(c[2]));
}

std::uint32_t colourOf(const processing::CloudPoint& p, const FusedSource& source, const FusedLook& look) {
    if (source.tint)
        return pack((*source.tint)[0], (*source.tint)[1], (*source.tint)[2]);
    switch (look.coloring) {
    case render::PointColoring::Camera:
        return pack(p.r, p.g, p.b);
    case render::PointColoring::Depth:
        return depthColour(look, p.z);
    case render::PointColoring::Confidence:
        return render::confidencePackedRgb(p.confidence) | kOpaque;
    }
    return pack(p.r, p.g, p.b);
}

} // namespace

frame::RigidTransform placeInWorld(const frame::Frame& frame, const frame::RigidTransform& correction) {
    const frame::RigidTransform own =
        frame.pose ? frame::rigidFromPose(*frame.pose) : frame::RigidTransform{};
    return frame::compose(correction, own);
}

namespace {

// The kept samples in the source's own camera frame.
std::vector<processing::CloudPoint> cameraCloud(const FusedSource& source, frame::Confidence minConfidence,
                                                float nearMeters) {
    if (!source.shown || !source.shown->cloud.depth.data)
        return {};
    const processing::ShownCloud& cloud = source.shown->cloud;
    const processing::CloudSamples samples{cloud.depth.data.get(), cloud.depth.intrinsics,
                                           cloud.colours.get()};
    return processing::buildPointCloud(samples, minConfidence, nearMeters);
}

std::array<float, 3> toWorld(const FusedSource& source, const processing::CloudPoint& p) {
    const auto w = source.cameraToWorld.apply({p.x, p.y, p.z});
    return {static_cast<float>(w[0]), static_cast<float>(w[1]), static_cast<float>(w[2])};
}

} // namespace

std::vector<processing::CloudPoint> worldCloud(const FusedSource& source, frame::Confidence minConfidence,
                                               float nearMeters) {
    auto points = cameraCloud(source, minConfidence, nearMeters);
    for (processing::CloudPoint& p : points) {
        const auto w = toWorld(source, p);
        p.x = w[0];
        p.y = w[1];
        p.z = w[2];
    }
    return points;
}

std::vector<processing::WorldPoint> fusedPoints(const std::vector<FusedSource>& sources,
                                                const FusedLook& look) {
    std::vector<processing::WorldPoint> out;
    for (const FusedSource& source : sources) {
        const auto points = cameraCloud(source, look.minConfidence, look.nearMeters);
        out.reserve(out.size() + points.size());
        for (const processing::CloudPoint& p : points) {
            const auto w = toWorld(source, p);
            out.push_back({w[0], w[1], w[2], colourOf(p, source, look)}); // coloured by its own depth
        }
    }
    return out;
}

} // namespace dc::ui
