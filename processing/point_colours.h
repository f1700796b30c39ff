#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace dc::processing {

// The packed RGBA colour of camera-image pixels, exactly as packing frame::pixelRgb's result gives it,
// at the cost of a table look-up: the table holds pixelRgb's own results for every YCbCr triplet, filled
// one chroma pair (256 lumas) at a time when a pair is first met, so only the colours a scene uses take
// memory.
class CameraColourTable {
public:
    CameraColourTable();
    // Prepares for the pixels of `image`; false when the image is empty or malformed.
    bool use(const frame::CapturedImage& image);
    // The colour of pixel (x, y), which must lie inside the image last passed to use().
    std::uint32_t rgba(int x, int y);
    // The same, when the table holds the pixel's chroma pair already; nothing when it does not. It only
    // reads, so threads may call it together while none calls rgba().
    std::optional<std::uint32_t> filledRgba(int x, int y) const;

private:
    std::uint32_t ycbcr(std::uint8_t y, std::uint8_t cb, std::uint8_t cr);
    bool filled(std::uint32_t pair) const { return pairsFilled_[pair / 64] >> (pair % 64) & 1; }
    // The pixel's colour, its YCbCr triplet converted by convert(y, cb, cr).
    template <class Convert> std::uint32_t colourAt(int x, int y, Convert&& convert) const;
    void fillPair(std::uint32_t pair);

    std::unique_ptr<std::uint32_t[]> ycbcr_;   // [cb][cr][y], rows valid where pairsFilled_ says so
    std::vector<std::uint64_t> pairsFilled_;   // one bit per (cb, cr)
    std::array<std::uint32_t, 256> rgbByte_{}; // RGB24: each channel's byte as pixelRgb and packing give it
    const std::uint8_t* bytes_ = nullptr;
    frame::PixelFormat format_ = frame::PixelFormat::Nv12;
    std::size_t width_ = 0, height_ = 0;
};

// The colour of each point of a width x height depth map: the camera-image pixel whose area matches the
// depth pixel's centre (cameraPixelOf), converted exactly as frame::pixelRgb does. Depth and image cover the
// same field of view at their own resolutions. Without a usable image every point is pixelRgb's mid-gray.
RgbImage pointColours(const frame::CapturedImage& image, int width, int height, CameraColourTable& table);
RgbImage pointColours(const frame::CapturedImage& image, int width, int height);

// R, G, B as the low three bytes of a little-endian RGBA8 word with alpha 255, as the GPU reads it.
inline std::uint32_t packRgba(const std::uint8_t* rgb) {
    return static_cast<std::uint32_t>(rgb[0]) | static_cast<std::uint32_t>(rgb[1]) << 8 |
           static_cast<std::uint32_t>(rgb[2]) << 16 | 0xff000000u;
}

} // namespace dc::processing
