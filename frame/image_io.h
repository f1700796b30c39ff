#pragma once

#include "base/expected.h"

#include <cstdint>
#include <string>

namespace dc::frame {

// Writes an 8-bit RGBA image (rows top to bottom, no padding) as PNG, atomically (base::writeFileAtomically).
Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba);

} // namespace dc::frame
