#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/shown_frame.h"

#include <string>
#include <vector>

namespace dc::exporting {

// What the cloud shows when a snapshot is taken: which of the shown depth's samples it draws and how
// they are coloured.
struct SnapshotCloud {
    frame::Confidence minConfidence = frame::Confidence::Low;
    float nearMeters = 0.0f;
    bool cameraColours = true; // coloured by the camera (else the colours the engine made, or none)
};

// Writes exactly the points drawn of `shown` (its depth, colours, the cloud's confidence and near limits) as
// a binary PLY at `path`, atomically. Colours a shader made for the screen are made once more here, on
// the CPU. `source` names where the frame came from in the file's comment.
Status writeSnapshotPly(const processing::ShownFrame& shown, const SnapshotCloud& cloud,
                        const std::string& source, const std::string& path);

// Writes each picture as a PNG into `directory`, then camera.png: the camera's image of `frame` at the
// resolution it was captured at (its panel shows it scaled), where there is a frame and it has one (a
// depth-only camera has none). Returns the names of the files written.
Expected<std::vector<std::string>> writePanels(const std::string& directory,
                                               const std::vector<processing::PanelPicture>& pictures,
                                               const frame::Frame* frame);

// A snapshot of `shown`: a directory under `parent` named after the frame, new each time (frame-N,
// frame-N-2, ...: two snapshots of one paused frame are two snapshots), holding the panels (writePanels)
// and the points drawn as cloud.ply (writeSnapshotPly). Returns that directory.
Expected<std::string> writeSnapshot(const std::string& parent,
                                    const std::vector<processing::PanelPicture>& pictures,
                                    const processing::ShownFrame& shown, const SnapshotCloud& cloud,
                                    const std::string& source);

} // namespace dc::exporting
