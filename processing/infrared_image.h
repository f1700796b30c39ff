#pragma once

#include "processing/camera_image.h"

#include <cstdint>

namespace dc::processing {

// The range of raw infrared intensities that the panel stretches to black..white.
struct IntensityRange {
    std::uint16_t low = 0;
    std::uint16_t high = 0;
    bool operator==(const IntensityRange&) const = default;
};

// The 1st and 99th percentile of the intensities: a few saturated pixels (a specular glint, the
// projector's dots) or dead ones do not flatten the rest of the image. {0, 0} for an empty image.
IntensityRange infraredContrastRange(const frame::Plane<std::uint16_t>& infrared);

// The infrared image as gray RGB at its own size, `range` stretched to 0..255 (below: black, above: white;
// a range of one value shows it black and anything brighter white).
RgbImage infraredRgbImage(const frame::Plane<std::uint16_t>& infrared, IntensityRange range);

} // namespace dc::processing
