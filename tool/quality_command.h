#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace dc::tool {

struct QualityOptions {
    std::string source = "synthetic";
    std::string roi;          // "X,Y,W,H" in depth pixels; empty: roiPercent
    double roiPercent = 40.0; // DQT's centred ROI, percent of width and of height
    std::string roiPolygon;   // "x,y;x,y;..." in depth pixel coordinates, at least 3 vertices; empty: none
    int frames = 30;          // frames captured; the noise window spans them all
    std::optional<double> groundTruthMm;
    std::optional<double> baselineMm; // a stereo camera's baseline: enables the subpixel RMS, expected noise
    double designSubpixelRms = 0.08;  // the camera's design subpixel accuracy, pixels
    double nearMeters = 0.0;
    double farMeters = 1e9;
    std::string confidence = "low";
    std::string expect; // "fillRate>=0.95,planeFitRmsMm<=2.0"
    std::string jsonPath;
    bool overwrite = false;
};

// `depthcloud quality`: Depth Quality Tool figures of a flat target in front of a source, headless; exit 1
// when an --expect does not hold, so a test rig can gate on it.
CLI::App* addQualityCommand(CLI::App& app, QualityOptions& options);
int runQuality(const QualityOptions& options);

} // namespace dc::tool
