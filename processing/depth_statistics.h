#pragma once

#include "frame/frame.h"
#include "processing/shown_frame.h"

#include <optional>

namespace dc::processing {

// The automatic colormap range: the 2nd to 98th percentile of the valid depth, so a few outliers do not
// flatten the ramp; at least a centimetre wide. None without a valid sample.
std::optional<DepthRangeMeters> percentileRange(const frame::Plane<float>& depthMeters);

// The median valid depth (1 m without one): the orbit's pivot, so the swing turns the cloud about the
// middle of the scene.
float medianDepth(const frame::Plane<float>& depthMeters);

} // namespace dc::processing
