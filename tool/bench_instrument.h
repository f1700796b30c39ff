#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchInstrumentOptions {
    int frames = 200;              // measured frames
    int budgetThousands = 1000;    // accumulate budget
    double voxelMillimetres = 1.0; // 1 mm keeps nearly every sample new: the worst case
    std::string jsonPath;
};

// `depthcloud bench instrument`: the per-frame cost of accumulate mode (CPU add + GPU upload) at a full
// budget, and of the stats panel.
CLI::App* addBenchInstrumentCommand(CLI::App& bench, BenchInstrumentOptions& options);
int runBenchInstrument(const BenchInstrumentOptions& options);

} // namespace dc::tool
