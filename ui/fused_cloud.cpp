#include "ui/fused_cloud.h"

#include "frame/world_placement.h"

namespace dc::ui {

// One definition below ui, which `depthcloud export` places its sources with too.
frame::RigidTransform placeInWorld(const frame::Frame& frame, const frame::RigidTransform& correction) {
    return frame::worldPlacement(frame, correction);
}

std::vector<processing::CloudPoint> worldCloud(const FusedSource& source, frame::Confidence minConfidence,
                                               float nearMeters) {
    if (!source.shown || !source.shown->cloud.depth.data)
        return {};
    const processing::ShownCloud& cloud = source.shown->cloud;
    const processing::CloudSamples samples{cloud.depth.data.get(), cloud.depth.intrinsics,
                                           cloud.colours.get()};
    auto points = processing::buildPointCloud(samples, minConfidence, nearMeters);
    for (processing::CloudPoint& p : points) {
        const auto w = source.cameraToWorld.apply({p.x, p.y, p.z});
        p.x = static_cast<float>(w[0]);
        p.y = static_cast<float>(w[1]);
        p.z = static_cast<float>(w[2]);
    }
    return points;
}

} // namespace dc::ui
