#include "processing/point_cloud.h"

#include "frame/color.h"
#include "processing/confidence_filter.h"

namespace dc::processing {

std::vector<CloudPoint> buildPointCloud(const frame::Frame& frame, frame::Confidence minLevel,
                                        float nearMeters) {
    std::vector<CloudPoint> points;
    if (!frame.sceneDepth || !frame.cameraIntrinsics.valid())
        return points;
    const frame::DepthData& depth = *frame.sceneDepth;
    const frame::Intrinsics k = frame.depthIntrinsics();
    const int w = depth.depthMeters.width, h = depth.depthMeters.height;
    const auto& image = frame.capturedImage;
    points.reserve(depth.depthMeters.pixels.size());
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const float z = depth.depthMeters.at(u, v);
            const std::uint8_t c = depth.confidence.empty() ? 2 : depth.confidence.at(u, v);
            if (!keepSample(z, c, minLevel, nearMeters))
                continue;
            const auto [x, y, zz] = unproject(u, v, z, k);
            const auto [cx, cy] = cameraPixelOf(u, v, w, h, image);
            const frame::Rgb rgb = frame::pixelRgb(image, cx, cy);
            points.push_back({x, y, zz, frame::toByte(rgb.r), frame::toByte(rgb.g), frame::toByte(rgb.b), c});
        }
    }
    return points;
}

} // namespace dc::processing
