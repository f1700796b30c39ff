#pragma once

#include <array>
#include <cstdint>

namespace dc::frame {

// Full-range BT.601 YCbCr, the encoding of ARKit's capturedImage and of the Depth Cloud sample's shader.
// All channels are normalised to [0, 1]; Cb and Cr are centred on 0.5.
struct Ycbcr {
    float y = 0.0f;
    float cb = 0.5f;
    float cr = 0.5f;
};

struct Rgb {
    float r = 0.0f;
    float g = 0.0f;
    float b = 0.0f;
};

// The sample's inverse matrix: R = Y + 1.402 Cr', G = Y - 0.3441 Cb' - 0.7141 Cr', B = Y + 1.772 Cb'.
// Results are not clamped, exactly like the shader; callers clamp when they store 8-bit values.
Rgb ycbcrToRgb(Ycbcr c);
// The forward transform whose inverse is ycbcrToRgb (to within the sample's 4-digit coefficients). Inline:
// the synthetic camera converts every pixel it renders.
inline Ycbcr rgbToYcbcr(Rgb c) {
    constexpr float kCbPerBlue = 1.0f / 1.772f, kCrPerRed = 1.0f / 1.402f; // multiplications, not divisions
    const float y = 0.299f * c.r + 0.587f * c.g + 0.114f * c.b;
    return {y, 0.5f + (c.b - y) * kCbPerBlue, 0.5f + (c.r - y) * kCrPerRed};
}

std::uint8_t toByte(float normalised);

} // namespace dc::frame

namespace dc::frame {
struct CapturedImage;
// The color of pixel (x, y) of a captured image in any supported format, converted to RGB in [0, 1].
// Coordinates are clamped to the image; an empty image gives mid-gray.
Rgb pixelRgb(const CapturedImage& image, int x, int y);
} // namespace dc::frame
