#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchSoakOptions {
    int frames = 10000;      // new frames shown
    int sampleEvery = 500;   // frames between memory and file-descriptor samples
    int warmupFrames = 2000; // growth is measured from here on
    std::string source = "synthetic:motion";
    std::string jsonPath;
};

// `depthcloud bench soak`: the viewer as the headless tool runs it, with every stage on (smoothing,
// upsampling, fog, aura, accumulation), for many frames; resident memory and open file descriptors sampled
// as it goes, and their growth after the warm-up.
CLI::App* addBenchSoakCommand(CLI::App& bench, BenchSoakOptions& options);
int runBenchSoak(const BenchSoakOptions& options);

} // namespace dc::tool
