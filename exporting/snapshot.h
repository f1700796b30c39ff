#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/shown_frame.h"

#include <string>

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

} // namespace dc::exporting
