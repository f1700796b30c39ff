#include "frame/color.h"

#include <algorithm>
#include <cmath>

namespace dc::frame {

Rgb ycbcrToRgb(Ycbcr c) {
    const float cb = c.cb - 0.5f;
    const float cr = c.cr - 0.5f;
    return {c.y + 1.402f * cr, c.y - 0.3441f * cb - 0.7141f * cr, c.y + 1.772f * cb};
}

std::uint8_t toByte(float normalised) {
    if (!(normalised > 0.0f)) // also maps NaN to 0
        return 0;
    return static_cast<std::uint8_t>(std::lround(std::min(normalised, 1.0f) * 255.0f));
}

} // namespace dc::frame

#include "frame/frame.h"

namespace dc::frame {

Rgb pixelRgb(const CapturedImage& image, int x, int y) {
    if (image.empty() || !image.raw() || image.width <= 0 || image.height <= 0 ||
        image.bytes->size() < CapturedImage::byteSize(image.format, image.width, image.height))
        return {0.5f, 0.5f, 0.5f};
    x = std::clamp(x, 0, image.width - 1);
    y = std::clamp(y, 0, image.height - 1);
    const std::uint8_t* b = image.bytes->data();
    const auto w = static_cast<std::size_t>(image.width);
    const auto n = [](std::uint8_t v) { return static_cast<float>(v) / 255.0f; };
    switch (image.format) {
    case PixelFormat::Nv12: {
        const std::uint8_t* chroma =
            b + w * image.height + (static_cast<std::size_t>(y / 2) * ((w + 1) / 2) + x / 2) * 2;
        return ycbcrToRgb({n(b[y * w + x]), n(chroma[0]), n(chroma[1])});
    }
    case PixelFormat::Yuyv: {
        const std::uint8_t* pair = b + static_cast<std::size_t>(y) * 4 * ((w + 1) / 2) + (x / 2) * 4;
        return ycbcrToRgb({n(pair[(x & 1) * 2]), n(pair[1]), n(pair[3])});
    }
    case PixelFormat::Rgb24: {
        const std::uint8_t* p = b + (static_cast<std::size_t>(y) * w + x) * 3;
        return {n(p[0]), n(p[1]), n(p[2])};
    }
    case PixelFormat::Jpeg:
        break;
    }
    return {0.5f, 0.5f, 0.5f};
}

} // namespace dc::frame
