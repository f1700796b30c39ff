#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchUpsampleOptions {
    std::string dataDirectory; // noisy-Middlebury scenes; empty: the synthetic scene only
    std::string jsonPath;      // also write every figure as JSON here
    std::string chartPath;     // error-versus-time chart (PNG)
    int runs = 10;             // timed runs per case; the median is reported
    bool quick = false;        // small synthetic frames, one Middlebury scene: the whole report in seconds
};

// `depthcloud bench upsample`: error against run time of every upsampling method, the ARKit-frame timings
// and the temporal-smoothing figures.
CLI::App* addBenchUpsampleCommand(CLI::App& bench, BenchUpsampleOptions& options);
int runBenchUpsample(const BenchUpsampleOptions& options);

} // namespace dc::tool
