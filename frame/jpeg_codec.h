#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace dc::frame {

// Camera images to JPEG and back with TurboJPEG, straight from and to the captured YCbCr planes. NV12 is
// stored as 4:2:0 JPEG and YUYV as 4:2:2; both are full-range BT.601 like JFIF's YCbCr, so neither
// direction converts colour (only NV12's interleaved chroma is split into planes and joined again).
// RGB24 is converted by TurboJPEG itself and stored 4:2:0. One encoder or decoder per thread.
class JpegEncoder {
public:
    JpegEncoder();
    ~JpegEncoder();
    JpegEncoder(JpegEncoder&&) noexcept;
    JpegEncoder& operator=(JpegEncoder&&) noexcept;

    // The JPEG of `image` at `quality` (1..100); it stays valid until the next call.
    Expected<std::span<const std::uint8_t>> encode(const CapturedImage& image, int quality);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

class JpegDecoder {
public:
    JpegDecoder();
    ~JpegDecoder();
    JpegDecoder(JpegDecoder&&) noexcept;
    JpegDecoder& operator=(JpegDecoder&&) noexcept;

    // Decodes a JPEG that must be `width` x `height`: to NV12 when it is 4:2:0 YCbCr, to YUYV when 4:2:2,
    // to RGB24 otherwise. Malformed or truncated data is an error, never a partly gray image.
    Expected<CapturedImage> decode(std::span<const std::uint8_t> jpeg, int width, int height);
    // The pixels of a camera's JPEG (PixelFormat::Jpeg) as above; an image of any other format as it is.
    Expected<CapturedImage> decode(const CapturedImage& image);
    // The size a JPEG's header announces, read without decoding it (microseconds, not milliseconds).
    Expected<std::pair<int, int>> size(std::span<const std::uint8_t> jpeg);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace dc::frame
