#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct DevicesOptions {
    bool all = false;        // also USB devices without a depth node
    bool json = false;       // machine-readable listing on stdout
    double watchSeconds = 0; // then print USB hotplug events for this long
};

struct BenchCaptureOptions {
    int frames = 200;
    int width = 1280;
    int height = 720;
    std::string jsonPath;
};

struct BenchLatencyOptions {
    std::string source;
    double seconds = 10.0;
    std::string jsonPath;
};

// `depthcloud devices`: depth-capable cameras (USB identity, V4L2 nodes with their modes, which node is
// depth/color/infrared, the --source that opens each) and, with --watch, USB hotplug events.
CLI::App* addDevicesCommand(CLI::App& app, DevicesOptions& options);
int runDevices(const DevicesOptions& options);

// `depthcloud bench capture`: CPU time per frame of the capture thread's conversions.
CLI::App* addBenchCaptureCommand(CLI::App& bench, BenchCaptureOptions& options);
int runBenchCapture(const BenchCaptureOptions& options);

// `depthcloud bench latency`: how old a live source's frames are when a consumer takes them (median, p99).
CLI::App* addBenchLatencyCommand(CLI::App& bench, BenchLatencyOptions& options);
int runBenchLatency(const BenchLatencyOptions& options);

} // namespace dc::tool
