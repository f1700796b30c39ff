#pragma once

#include "base/expected.h"
#include "devices/replay/replay_source.h"
#include "frame/camera_model.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace dc::exporting {

enum class ExportFormat {
    Ply,   // one binary PLY per frame: x y z (meters, camera frame) red green blue confidence
    Stray, // the Stray Scanner layout, which our importer (and Stray's tools) read back
    Png16, // depth/NNNNNN.png, 16-bit millimetres, 0 = no measurement
    Mcap,  // one MCAP file of ROS 2 messages (exporting/mcap_export.h), for Foxglove, rerun, ros2 bag
};

const char* toString(ExportFormat format);

// Frames [first, end) of a source.
struct FrameRange {
    std::size_t first = 0;
    std::size_t end = 0;
};

// "A:B" (B excluded), "A:" or ":B", against a source of `count` frames; errors name the problem.
Expected<FrameRange> parseFrameRange(const std::string& text, std::size_t count);

struct ExportOptions {
    ExportFormat format = ExportFormat::Ply;
    std::string outDirectory;      // Mcap: the file to write
    FrameRange frames;             // end == 0: to the last frame
    bool worldCoordinates = false; // PLY: points through the frame's pose (when it has one)
    // Applied to each frame before it is written, in order (the instrument's processing: smoothing and
    // upsampling make the depth that was shown, which then replaces sceneDepth). None: frames as recorded.
    std::function<frame::Frame(frame::Frame)> transform;
    bool overwrite = false; // Mcap: replace an existing file (the directory formats replace their files)
};

struct ExportResult {
    std::size_t framesWritten = 0;
    std::size_t framesSkipped = 0; // unreadable frames, each logged with its error
};

// The frames [first, end) that `requested` (end == 0: to the last frame) covers of a source of `count`
// frames; an error when they are not within it.
Expected<FrameRange> framesWithin(const FrameRange& requested, std::size_t count);

// One source's part of a fused PLY: its frame, where that frame's camera sits in the world and the
// source's name (its --source).
struct PlacedFrame {
    const frame::Frame* frame = nullptr;
    std::size_t index = 0; // the frame's index in its source
    frame::RigidTransform cameraToWorld;
    std::string name;
};

// Every part's points (as the PLY export builds them) in the world frame, part after part, as one PLY at
// DIRECTORY/NNNNNN.ply, NNNNNN the first part's frame index, written atomically. Its comments count each
// part's points as the window's fused cloud.ply does ("N points of NAME") and say which frame each came from.
Status writeFusedPly(const std::vector<PlacedFrame>& parts, const std::string& directory);

// Called after each frame with (frames done, frames in the range); returning false cancels the export.
using ExportProgress = std::function<bool(std::size_t done, std::size_t total)>;

// Writes the frames of `source` to options.outDirectory (created when missing), every file atomically (an
// MCAP file appears only once complete, and never replaces one unless options.overwrite).
// Runs on the calling thread (the UI calls it from a worker with a source of its own: sources are not
// thread-safe). Unreadable frames are skipped with a warning; a write failure ends the export.
Expected<ExportResult> exportFrames(devices::replay::ReplaySource& source, const ExportOptions& options,
                                    const ExportProgress& progress = {});

} // namespace dc::exporting
