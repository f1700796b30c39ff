#include "processing/point_cloud.h"

#include "frame/color.h"
#include "processing/confidence_filter.h"
#include "processing/point_colours.h"
#include "processing/registration.h"

namespace dc::processing {

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
                samples.colours ? &samples.colours->pixels[(static_cast<std::size_t>(v) * w + u) * 3] : nullptr;
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

} // namespace dc::processing
