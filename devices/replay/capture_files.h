#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <string>

// Reading the image and text files that capture directories are made of, with errors that name them.
namespace dc::devices::replay {

Expected<std::string> readTextFile(const std::string& path);

// A 16-bit single-channel PNG (depth in integer units) converted to meters with depthFromUnits.
Expected<frame::Plane<float>> readDepthPng(const std::string& path, double metersPerUnit);
// An 8-bit single-channel PNG (confidence 0/1/2).
Expected<frame::Plane<std::uint8_t>> readConfidencePng(const std::string& path);
// A PNG (gray or colour, 8 or 16 bits) or JPEG colour image, as packed 8-bit RGB.
Expected<frame::CapturedImage> readColorImage(const std::string& path);

} // namespace dc::devices::replay
