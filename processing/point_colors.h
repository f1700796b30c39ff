#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace dc::processing {

// The packed RGBA colour of camera-image pixels, exactly as packing frame::pixelRgb's result gives it,
// without pixelRgb's per-call checks: the same conversion (frame::ycbcrToRgb on the same normalised
// values) and the same rounding, per pixel. A table of every YCbCr triplet's result was tried first; its
// 64 MB made each look-up a cache miss, several times the cost of the arithmetic.
class CameraColourTable {
public:
    CameraColourTable();
    // Prepares for the pixels of `image`; false when the image is empty or malformed.
    bool use(const frame::CapturedImage& image);
    // The colour of pixel (x, y), which must lie inside the image last passed to use().
    std::uint32_t rgba(int x, int y) const;

private:
    std::uint32_t ycbcr(std::uint8_t y, std::uint8_t cb, std::uint8_t cr) const;

    std::array<float, 256> normalised_{};      // pixelRgb's byte / 255.0f
    std::array<std::uint32_t, 256> rgbByte_{}; // RGB24: each channel's byte as pixelRgb and packing give it
    const std::uint8_t* bytes_ = nullptr;
    frame::PixelFormat format_ = frame::PixelFormat::Nv12;
    std::size_t width_ = 0, height_ = 0;
};

// The colour of each point of a width x height depth map: the camera-image pixel whose area matches the
// depth pixel's centre (cameraPixelOf), converted exactly as frame::pixelRgb does. Depth and image cover the
// same field of view at their own resolutions. Without a usable image every point is pixelRgb's mid-gray.
RgbImage pointColors(const frame::CapturedImage& image, int width, int height, CameraColourTable& table);
RgbImage pointColors(const frame::CapturedImage& image, int width, int height);

// R, G, B as the low three bytes of a little-endian RGBA8 word with alpha 255, as the GPU reads it.
inline std::uint32_t packRgba(const std::uint8_t* rgb) {
    return static_cast<std::uint32_t>(rgb[0]) | static_cast<std::uint32_t>(rgb[1]) << 8 |
           static_cast<std::uint32_t>(rgb[2]) << 16 | 0xff000000u;
}

} // namespace dc::processing
