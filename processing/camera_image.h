#pragma once

#include "frame/frame.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dc::processing {

// Rows of 8-bit single-channel pixels that somebody else owns.
struct GrayView {
    const std::uint8_t* pixels = nullptr;
    int width = 0;
    int height = 0;
    std::ptrdiff_t stride = 0; // bytes from one row to the next

    bool empty() const { return pixels == nullptr || width <= 0 || height <= 0; }
};

// Rows of 8-bit three-channel pixels that somebody else owns.
struct ColorView {
    const std::uint8_t* pixels = nullptr;
    int width = 0;
    int height = 0;
    std::ptrdiff_t stride = 0; // bytes from one row to the next

    bool empty() const { return pixels == nullptr || width <= 0 || height <= 0; }
};

// An 8-bit RGB image, rows top to bottom without padding: point colours, the camera panel's image.
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;
    bool empty() const { return pixels.empty(); }
};

// An 8-bit RGBA image, rows top to bottom without padding, ready for a texture or writeRgbaPng.
struct RgbaImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;

    bool empty() const { return pixels.empty(); }
};

// The luma (full-range BT.601 Y) of a captured image: NV12's Y plane in place, YUYV and RGB24 converted
// into `scratch`. Empty for an empty or malformed image.
GrayView lumaView(const frame::CapturedImage& image, std::vector<std::uint8_t>& scratch);

// The image resampled to width x height (area-averaged when shrinking) as packed 8-bit RGB, converted with
// full-range BT.601 as the sample's matrix (frame::ycbcrToRgb, to 0.2 levels). Empty for an empty or
// malformed image.
std::vector<std::uint8_t> cameraRgb(const frame::CapturedImage& image, int width, int height);

// Buffers that cameraRgbView() keeps between frames.
struct RgbScratch {
    std::vector<std::uint8_t> luma, chroma, ycrcb, rgb;
};

// cameraRgb() into `scratch`, whose buffers keep their capacity: once they have the size, a frame
// allocates nothing (on a virtual machine, first-touch page faults of a few fresh megabytes per frame
// cost milliseconds). The view points into `scratch`.
ColorView cameraRgbView(const frame::CapturedImage& image, int width, int height, RgbScratch& scratch);

// The size the camera panel's image is made at: the width it is shown at, in steps (so resizing the panel
// does not redo it every frame), never above the image's own width; the height keeps the image's aspect.
std::array<int, 2> cameraPanelImageSize(const frame::CapturedImage& image, int shownWidth);

// cameraRgb as an RgbImage (empty when cameraRgb is).
RgbImage cameraRgbImage(const frame::CapturedImage& image, int width, int height);

// Half the camera image's size, rounded up: the resolution of the fog and aura images (960x720 for ARKit's
// 1920x1440), which the point-cloud sample also uses for its depth texture.
inline std::array<int, 2> halfCameraSize(const frame::CapturedImage& image) {
    return {(image.width + 1) / 2, (image.height + 1) / 2};
}

} // namespace dc::processing
