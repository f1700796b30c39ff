#pragma once

#include "frame/camera_model.h"
#include "processing/point_cloud.h"
#include "processing/shown_frame.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace dc::ui {

// One source's part of the fused cloud: the result it shows and where its camera sits in the world.
struct FusedSource {
    processing::ShownFramePtr shown;
    frame::RigidTransform cameraToWorld;
    std::string name;                               // its --source, for a file's comments
    std::optional<frame::Confidence> minConfidence; // its own; none: the main source's
    bool operator==(const FusedSource&) const = default;
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

} // namespace dc::ui
