#pragma once

#include "frame/frame.h"
#include "processing/shown_frame.h"

#include <optional>

namespace dc::processing {

// The automatic colormap range: the 2nd to 98th percentile of the valid depth, so a few outliers do not
// flatten the ramp; at least a centimetre wide. None without a valid sample.
std::optional<DepthRangeMeters> percentileRange(const frame::Plane<float>& depthMeters);

// The automatic range over time: each new frame moves the range shown `fraction` of the way to that frame's
// percentiles, so the colours follow the scene without pumping with every frame's outliers. None before:
// the frame's range as it is.
DepthRangeMeters followRange(const std::optional<DepthRangeMeters>& shown, const DepthRangeMeters& frame,
                             float fraction);

// The median valid depth (1 m without one): the orbit's pivot, so the swing turns the cloud about the
// middle of the scene.
float medianDepth(const frame::Plane<float>& depthMeters);

} // namespace dc::processing
