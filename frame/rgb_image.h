#pragma once

#include "frame/frame.h"

#include <cstdint>
#include <vector>

namespace dc::frame {

// Packed 8-bit RGB of a captured image in any supported format (full-range BT.601 for NV12 and YUYV,
// the same conversion as every other consumer through pixelRgb). Empty for an empty image.
std::vector<std::uint8_t> toRgb24(const CapturedImage& image);

// Wraps packed RGB bytes as a captured image.
CapturedImage makeRgb24Image(int width, int height, std::vector<std::uint8_t> rgb);

} // namespace dc::frame
