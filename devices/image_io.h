#pragma once

#include "devices/expected.h"

#include <cstdint>
#include <span>
#include <string>

namespace dc::devices {

// Writes `bytes` under a temporary name in the directory of `path` and renames it over `path` only
// once complete, so a failure never leaves a half-written file in place of a good one.
Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);

// Writes an 8-bit RGBA image (rows top to bottom, no padding) as PNG, atomically.
Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba);

// Writes `text` to `path` with the same temporary-name-then-rename guarantee.
Status writeTextFile(const std::string& path, const std::string& text);

} // namespace dc::devices
