#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchQualityOptions {
    int frames = 60; // measured frames per case
    std::string jsonPath;
};

// `depthcloud bench quality`: what the depth-quality figures cost per frame on 1280x720 depth of the
// synthetic scene, with DQT's centred 40 % ROI and with the whole map: every per-frame figure together,
// each part alone, and DQT's own plain plane fit over the same points (the figure Intel's tool computes)
// as the baseline, in the same run.
CLI::App* addBenchQualityCommand(CLI::App& bench, BenchQualityOptions& options);
int runBenchQuality(const BenchQualityOptions& options);

} // namespace dc::tool
