#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchCameraOptions {
    double seconds = 5.0; // measured per case, after a second of warm-up
    double fps = 30.0;    // the camera's rate
    std::string only;     // one case by name (empty: every case)
    std::string jsonPath;
};

// `depthcloud bench camera`: what a person streaming a real camera meets, end to end. Pre-made frames of a
// camera's size arrive at its rate (so the source costs nothing), the viewer runs as the window runs it
// (default view and panels, 1280x720, paced to a 60 Hz display, drawn where the picture changed), and it
// reports frames shown against delivered, where the others were dropped, arrival-to-screen latency, the GL
// thread's and the whole process's CPU per frame, and a bare GL_POINTS draw of the same samples. The last
// case streams two such cameras at once, fused in one cloud, and counts each one's frames.
CLI::App* addBenchCameraCommand(CLI::App& bench, BenchCameraOptions& options);
int runBenchCamera(const BenchCameraOptions& options);

} // namespace dc::tool
