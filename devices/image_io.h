#pragma once

#include "devices/expected.h"

#include <cstdint>
#include <string>

namespace dc::devices {

// Writes an 8-bit RGBA image (rows top to bottom, no padding) as PNG. The file is written under a
// temporary name in the same directory and renamed over `path` only once complete, so a failure never
// leaves a half-written file in place of a good one.
Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba);

// Writes `text` to `path` with the same temporary-name-then-rename guarantee.
Status writeTextFile(const std::string& path, const std::string& text);

} // namespace dc::devices
