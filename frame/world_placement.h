#pragma once

#include "frame/camera_model.h"
#include "frame/frame.h"

namespace dc::frame {

// Where a frame's camera sits in the world: its pose (pose=, /tf, a recording's), else the world's origin,
// then moved by `correction`, which acts in the world frame: the Sources panel's nudges or ICP's refinement
// in the window (ui::placeInWorld), a source's pose= in a fused export (placed as Device::place places it).
inline RigidTransform worldPlacement(const Frame& frame, const RigidTransform& correction) {
    const RigidTransform own = frame.pose ? rigidFromPose(*frame.pose) : RigidTransform{};
    return compose(correction, own);
}

} // namespace dc::frame
