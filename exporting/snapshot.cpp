#include "exporting/snapshot.h"

#include "base/files.h"
#include "exporting/ply.h"
#include "frame/image_io.h"
#include "frame/jpeg_codec.h"
#include "frame/rgb_image.h"
#include "processing/point_cloud.h"
#include "processing/registration.h"

#include <algorithm>
#include <memory>

namespace dc::exporting {

namespace {

Status writeCameraPng(const frame::Frame& frame, const std::string& path) {
    // A JPEG camera's image is decoded only for what shows it; the snapshot is one more reader.
    const auto captured = frame::JpegDecoder().decode(frame.capturedImage);
    if (!captured)
        return Error{"cannot write camera.png: " + captured.error().message};
    // At its own size, converted as the Stray export converts it (resampling is cameraRgb's work).
    const std::vector<std::uint8_t> rgb = frame::toRgb24(*captured);
    if (rgb.empty())
        return Error{"cannot write camera.png: the camera image is malformed"};
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(captured->width) * captured->height * 4, 255);
    for (std::size_t i = 0, n = rgba.size() / 4; i < n; ++i)
        std::copy_n(&rgb[i * 3], 3, &rgba[i * 4]);
    return frame::writeRgbaPng(path, captured->width, captured->height, rgba.data());
}

} // namespace

Status writeSnapshotPly(const processing::ShownFrame& shown, const SnapshotCloud& cloud,
                        const std::string& source, const std::string& path) {
    processing::CloudSamples samples = shown.samples();
    std::shared_ptr<const processing::RgbImage> colours;
    if (!samples.colours && samples.depth && cloud.cameraColours) {
        processing::CameraColourTable table;
        colours = processing::framePointColours(*shown.frame, samples.depth->depthMeters, table).colours;
        samples.colours = colours.get();
    }
    const auto points = processing::buildPointCloud(samples, cloud.minConfidence, cloud.nearMeters);
    return base::writeFileAtomically(path, encodePly(points, {"depthcloud snapshot of " + source}));
}

Expected<std::vector<std::string>> writePanels(const std::string& directory,
                                               const std::vector<processing::PanelPicture>& pictures,
                                               const frame::Frame* frame) {
    std::vector<std::string> written;
    for (const processing::PanelPicture& p : pictures) {
        const processing::RgbaImage& image = p.image;
        if (Status s = frame::writeRgbaPng(directory + "/" + p.fileName, image.width, image.height,
                                           image.pixels.data());
            !s)
            return s.error();
        written.push_back(p.fileName);
    }
    if (!frame || frame->capturedImage.empty())
        return written;
    if (Status s = writeCameraPng(*frame, directory + "/camera.png"); !s)
        return s.error();
    written.emplace_back("camera.png");
    return written;
}

Expected<std::string> writeSnapshot(const std::string& parent,
                                    const std::vector<processing::PanelPicture>& pictures,
                                    const processing::ShownFrame& shown, const SnapshotCloud& cloud,
                                    const std::string& source) {
    auto dir = base::createFreshDirectory(parent, "frame-" + std::to_string(shown.frame->sequence));
    if (!dir)
        return dir.error();
    if (auto written = writePanels(*dir, pictures, shown.frame.get()); !written)
        return written.error();
    if (Status s = writeSnapshotPly(shown, cloud, source, *dir + "/cloud.ply"); !s)
        return s.error();
    return dir;
}

} // namespace dc::exporting
