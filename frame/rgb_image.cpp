#include "frame/rgb_image.h"

#include "frame/color.h"

#include <algorithm>

namespace dc::frame {

namespace {

// toByte without its NaN guard and lround: ycbcrToRgb of 8-bit input is always finite.
std::uint8_t fastByte(float normalised) {
    return static_cast<std::uint8_t>(std::clamp(normalised * 255.0f + 0.5f, 0.0f, 255.0f));
}

void put(std::uint8_t*& out, std::uint8_t y, std::uint8_t cb, std::uint8_t cr) {
    constexpr float kScale = 1.0f / 255.0f;
    const Rgb c = ycbcrToRgb({y * kScale, cb * kScale, cr * kScale});
    *out++ = fastByte(c.r);
    *out++ = fastByte(c.g);
    *out++ = fastByte(c.b);
}

} // namespace

std::vector<std::uint8_t> toRgb24(const CapturedImage& image) {
    if (image.empty() || !image.raw() || image.width <= 0 || image.height <= 0 ||
        image.bytes->size() < CapturedImage::byteSize(image.format, image.width, image.height))
        return {};
    const auto w = static_cast<std::size_t>(image.width);
    const std::uint8_t* b = image.bytes->data();
    if (image.format == PixelFormat::Rgb24)
        return {b, b + 3 * w * image.height};
    // Whole rows at a time: a per-pixel pixelRgb call costs several times more at camera resolutions.
    std::vector<std::uint8_t> rgb(3 * w * image.height);
    std::uint8_t* out = rgb.data();
    for (std::size_t y = 0; y < static_cast<std::size_t>(image.height); ++y) {
        if (image.format == PixelFormat::Nv12) {
            const std::uint8_t* luma = b + y * w;
            const std::uint8_t* chroma = b + w * image.height + (y / 2) * ((w + 1) / 2) * 2;
            for (std::size_t x = 0; x < w; ++x)
                put(out, luma[x], chroma[(x / 2) * 2], chroma[(x / 2) * 2 + 1]);
        } else {
            const std::uint8_t* row = b + y * 4 * ((w + 1) / 2);
            for (std::size_t x = 0; x < w; ++x)
                put(out, row[(x / 2) * 4 + (x & 1) * 2], row[(x / 2) * 4 + 1], row[(x / 2) * 4 + 3]);
        }
    }
    return rgb;
}

CapturedImage makeRgb24Image(int width, int height, std::vector<std::uint8_t> rgb) {
    return {PixelFormat::Rgb24, width, height,
            std::make_shared<const std::vector<std::uint8_t>>(std::move(rgb))};
}

} // namespace dc::frame
