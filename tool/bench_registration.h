#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace dc::tool {

struct BenchRegistrationOptions {
    int runs = 30; // measured runs per case
    std::string jsonPath;
};

// `depthcloud bench registration`: colouring the points of a two-sensor camera (848x480 depth registered
// into 1280x720 colour on the synthetic rig) on one thread and on two, against the single-camera colouring
// of the same sizes measured in the same run.
CLI::App* addBenchRegistrationCommand(CLI::App& bench, BenchRegistrationOptions& options);
int runBenchRegistration(const BenchRegistrationOptions& options);

} // namespace dc::tool
