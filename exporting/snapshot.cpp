#include "exporting/snapshot.h"

#include "base/files.h"
#include "exporting/ply.h"
#include "processing/camera_image.h"
#include "processing/point_cloud.h"
#include "processing/registration.h"

#include <memory>

namespace dc::exporting {

Status writeSnapshotPly(const processing::ShownFrame& shown, const SnapshotCloud& cloud,
                        const std::string& source, const std::string& path) {
    processing::CloudSamples samples = shown.samples();
    std::shared_ptr<const processing::RgbImage> colours;
    if (!samples.colors && samples.depth && cloud.cameraColours) {
        processing::CameraColorTable table;
        colours = processing::framePointColours(*shown.frame, samples.depth->depthMeters, table).colors;
        samples.colors = colours.get();
    }
    const auto points = processing::buildPointCloud(samples, cloud.minConfidence, cloud.nearMeters);
    return base::writeFileAtomically(path, encodePly(points, {"depthcloud snapshot of " + source}));
}

} // namespace dc::exporting
