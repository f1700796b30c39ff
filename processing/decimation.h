#pragma once

#include "frame/frame.h"

#include <cstddef>
#include <memory>

namespace dc::processing {

// The samples the cloud draws when it draws fewer than the depth map holds: each factor x factor cell of
// the map becomes one sample, the nearest of the cell's samples that the cloud would draw (so a cell
// keeps the surface in front, as a depth test would, and never loses a point to a culled neighbour).
// Placed at the cell's centre: the intrinsics are the map's divided by the factor, as RealSense's
// decimation filter does. Colours are made afterwards for the kept samples alone, where they are drawn.
struct DecimatedDepth {
    std::shared_ptr<const frame::DepthData> data; // confidence of the kept sample; 0 depth: none kept
    frame::Intrinsics intrinsics;
};

// The smallest factor at which a width x height map has at most `maxPoints` cells (1 when it already has,
// or when maxPoints is 0 = unknown).
int footprintFactor(int width, int height, std::size_t maxPoints);

// Decimates `depth` by `factor` (>= 2) keeping the nearest drawable sample of each cell (keepSample with
// minLevel and nearMeters).
DecimatedDepth decimateNearest(const frame::DepthData& depth, const frame::Intrinsics& intrinsics, int factor,
                               frame::Confidence minLevel, float nearMeters);

// Every `step`-th sample of `depth` in each direction (step >= 2), the one nearest the centre of its
// step x step cell, with its confidence: what a panel shows of the map under nearest sampling when it is
// shown at 1/step of the map's size, so a panel can be drawn from these instead of the whole map.
frame::DepthData sampleCellCentres(const frame::DepthData& depth, int step);

// The step a panel shown `shownWidth` pixels wide draws a `mapWidth`-wide map at: 1 (every sample) while
// it is shown at least half as wide as the map, or at an unknown width (0).
int panelSampleStep(int mapWidth, int shownWidth);

} // namespace dc::processing
