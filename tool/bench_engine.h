#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchEngineOptions {
    int frames = 100;        // measured viewer frames
    double sourceFps = 60.0; // the camera's rate
    double viewerFps = 30.0; // the viewer's, slower than the source: latest wins
    std::string jsonPath;
};

// `depthcloud bench engine`: what the GL thread pays per frame with every stage on, now that processing
// runs on the frame processor's thread, against the same work done inline on the calling thread (what the
// viewer did before); the processing latency; frames processed against frames shown.
CLI::App* addBenchEngineCommand(CLI::App& bench, BenchEngineOptions& options);
int runBenchEngine(const BenchEngineOptions& options);

} // namespace dc::tool
