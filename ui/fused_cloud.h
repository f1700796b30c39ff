#pragma once

#include "frame/camera_model.h"
#include "processing/point_accumulator.h"
#include "processing/shown_frame.h"
#include "render/point_cloud_renderer.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace dc::ui {

// One source's part of the fused cloud: the result it shows and where its camera sits in the world.
struct FusedSource {
    processing::ShownFramePtr shown;
    frame::RigidTransform cameraToWorld;
    // Every point of the source in this colour (R, G, B), so that each source can be told apart.
    std::optional<std::array<std::uint8_t, 3>> tint;
    std::string name; // its --source, for a file's comments
    bool operator==(const FusedSource&) const = default;
};

// How the fused points are kept and coloured: the cloud panel's own settings.
struct FusedLook {
    frame::Confidence minConfidence = frame::Confidence::Low;
    float nearMeters = 0.1f;
    render::PointColoring coloring = render::PointColoring::Camera;
    render::Colormap colormap = render::Colormap::Jet;
    float rangeMinMeters = 0.0f;
    float rangeMaxMeters = 2.5f;
    bool operator==(const FusedLook&) const = default;
};

// How a companion joins the fused cloud, as the Sources panel sets it.
struct CompanionLook {
    bool visible = true;
    bool tinted = false;
    std::array<float, 3> tint{1.0f, 0.55f, 0.1f};
    // Moves the source in the world after its own pose (ICP's refinement, or the panel's nudges).
    frame::RigidTransform correction;
};

// Where a source's camera sits: its frame's pose (pose=, /tf, a recording's), else the world's origin,
// then moved by `correction` (the Sources panel's, or ICP's), which acts in the world frame.
frame::RigidTransform placeInWorld(const frame::Frame& frame, const frame::RigidTransform& correction);

// The kept samples of `source`'s shown cloud (confidence and near limit as given) with their own colours,
// moved into the world.
std::vector<processing::CloudPoint> worldCloud(const FusedSource& source, frame::Confidence minConfidence,
                                               float nearMeters);

// The kept samples of every source's shown cloud (the samples the cloud draws of each: confidence and
// near limit as `look` says) moved into the world, each coloured as the cloud colours its own points or
// by its tint. A source without a cloud adds nothing.
std::vector<processing::WorldPoint> fusedPoints(const std::vector<FusedSource>& sources,
                                                const FusedLook& look);

} // namespace dc::ui
