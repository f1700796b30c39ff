#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace dc::tool {

struct AlignOptions {
    std::vector<std::string> sources; // two: A, the reference, then B, whose placement is refined
    std::string savePath;   // OpenCV extrinsics: camera_0 = A's placement, camera_1 = B's refined one
    std::string kalibrPath; // Kalibr camchain: cam0 = A (which must sit at the world's origin), cam1 = B
    std::string jsonPath;
    std::string plyPath; // both clouds fused in the world frame, B placed where ICP put it
    bool overwrite = false;
};

// `depthcloud align`: how well two cameras' clouds agree where they overlap, placed by their poses (pose=,
// /tf, a recording's poses), and the point-to-plane ICP that refines B's placement against A's: the overlap
// figure before and after, the correction, the time; the refined placements saved in the extrinsics formats
// pose=FILE reads back. Headless.
CLI::App* addAlignCommand(CLI::App& app, AlignOptions& options);
int runAlign(const AlignOptions& options);

} // namespace dc::tool
