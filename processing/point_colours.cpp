#include "processing/point_colours.h"

#include "frame/color.h"
#include "processing/point_cloud.h"

#include <algorithm>

namespace dc::processing {

namespace {

std::uint32_t packRgba(const frame::Rgb& c) {
    return static_cast<std::uint32_t>(frame::toByte(c.r)) |
           static_cast<std::uint32_t>(frame::toByte(c.g)) << 8 |
           static_cast<std::uint32_t>(frame::toByte(c.b)) << 16 | 0xff000000u;
}

frame::CapturedImage tinyImage(frame::PixelFormat format, int width, std::vector<std::uint8_t> bytes) {
    return {format, width, 1, std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
}

void storeRgb(std::uint32_t rgba, std::uint8_t* out) {
    out[0] = static_cast<std::uint8_t>(rgba);
    out[1] = static_cast<std::uint8_t>(rgba >> 8);
    out[2] = static_cast<std::uint8_t>(rgba >> 16);
}

} // namespace

CameraColourTable::CameraColourTable()
    : ycbcr_(new std::uint32_t[std::size_t{1} << 24]), pairsFilled_((std::size_t{1} << 16) / 64) {
    for (int v = 0; v < 256; ++v) {
        const auto b = static_cast<std::uint8_t>(v);
        rgbByte_[static_cast<std::size_t>(v)] =
            packRgba(frame::pixelRgb(tinyImage(frame::PixelFormat::Rgb24, 1, {b, b, b}), 0, 0)) & 0xffu;
    }
}

bool CameraColourTable::use(const frame::CapturedImage& image) {
    if (image.empty() || !image.raw() || image.width <= 0 || image.height <= 0 ||
        image.bytes->size() < frame::CapturedImage::byteSize(image.format, image.width, image.height))
        return false;
    bytes_ = image.bytes->data();
    format_ = image.format;
    width_ = static_cast<std::size_t>(image.width);
    height_ = static_cast<std::size_t>(image.height);
    return true;
}

// The same addressing as frame::pixelRgb; the conversion itself is pixelRgb's, through the table.
template <class Convert> std::uint32_t CameraColourTable::colourAt(int xi, int yi, Convert&& convert) const {
    const auto x = static_cast<std::size_t>(xi), y = static_cast<std::size_t>(yi);
    switch (format_) {
    case frame::PixelFormat::Nv12: {
        const std::uint8_t* chroma = bytes_ + width_ * height_ + ((y / 2) * ((width_ + 1) / 2) + x / 2) * 2;
        return convert(bytes_[y * width_ + x], chroma[0], chroma[1]);
    }
    case frame::PixelFormat::Yuyv: {
        const std::uint8_t* pair = bytes_ + y * 4 * ((width_ + 1) / 2) + (x / 2) * 4;
        return convert(pair[(x & 1) * 2], pair[1], pair[3]);
    }
    case frame::PixelFormat::Rgb24: {
        const std::uint8_t* p = bytes_ + (y * width_ + x) * 3;
        return rgbByte_[p[0]] | rgbByte_[p[1]] << 8 | rgbByte_[p[2]] << 16 | 0xff000000u;
    }
    case frame::PixelFormat::Jpeg:
        break;
    }
    return 0xff808080u;
}

std::uint32_t CameraColourTable::rgba(int x, int y) {
    return colourAt(x, y,
                    [this](std::uint8_t l, std::uint8_t cb, std::uint8_t cr) { return ycbcr(l, cb, cr); });
}

std::optional<std::uint32_t> CameraColourTable::filledRgba(int x, int y) const {
    bool missing = false;
    const std::uint32_t rgba = colourAt(x, y, [&](std::uint8_t l, std::uint8_t cb, std::uint8_t cr) {
        const std::uint32_t pair = static_cast<std::uint32_t>(cb) << 8 | cr;
        missing = !filled(pair);
        return missing ? 0u : ycbcr_[std::size_t{pair} << 8 | l];
    });
    return missing ? std::nullopt : std::optional<std::uint32_t>(rgba);
}

std::uint32_t CameraColourTable::ycbcr(std::uint8_t y, std::uint8_t cb, std::uint8_t cr) {
    const std::uint32_t pair = static_cast<std::uint32_t>(cb) << 8 | cr;
    if (!filled(pair))
        fillPair(pair);
    return ycbcr_[std::size_t{pair} << 8 | y];
}

// pixelRgb of a 2x1 NV12 image for each luma, so the table holds exactly what pixelRgb computes.
void CameraColourTable::fillPair(std::uint32_t pair) {
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(4);
    (*bytes)[2] = static_cast<std::uint8_t>(pair >> 8);
    (*bytes)[3] = static_cast<std::uint8_t>(pair & 0xff);
    const frame::CapturedImage image{frame::PixelFormat::Nv12, 2, 1, bytes};
    for (std::uint32_t y = 0; y < 256; ++y) {
        (*bytes)[0] = static_cast<std::uint8_t>(y);
        ycbcr_[std::size_t{pair} << 8 | y] = packRgba(frame::pixelRgb(image, 0, 0));
    }
    pairsFilled_[pair / 64] |= std::uint64_t{1} << (pair % 64);
}

RgbImage pointColours(const frame::CapturedImage& image, int width, int height, CameraColourTable& table) {
    RgbImage out{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3)};
    if (!table.use(image)) {
        const std::uint32_t gray = packRgba(frame::pixelRgb(image, 0, 0));
        for (std::size_t i = 0; i < out.pixels.size(); i += 3)
            storeRgb(gray, &out.pixels[i]);
        return out;
    }
    for (int v = 0; v < height; ++v) {
        std::uint8_t* row = out.pixels.data() + static_cast<std::size_t>(v) * width * 3;
        for (int u = 0; u < width; ++u) {
            const auto [x, y] = cameraPixelOf(u, v, width, height, image);
            storeRgb(table.rgba(std::clamp(x, 0, image.width - 1), std::clamp(y, 0, image.height - 1)),
                     row + static_cast<std::size_t>(u) * 3);
        }
    }
    return out;
}

RgbImage pointColours(const frame::CapturedImage& image, int width, int height) {
    CameraColourTable table;
    return pointColours(image, width, height, table);
}

} // namespace dc::processing
