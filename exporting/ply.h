#pragma once

#include "processing/point_cloud.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dc::exporting {

// A binary little-endian PLY of the points: float x y z, uchar red green blue, uchar confidence (0 low,
// 1 medium, 2 high). Open3D and CloudCompare read it; `comment` lines say where it came from.
std::vector<std::uint8_t> encodePly(const std::vector<processing::CloudPoint>& points,
                                    const std::vector<std::string>& comments);

} // namespace dc::exporting
