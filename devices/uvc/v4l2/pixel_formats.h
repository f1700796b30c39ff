#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace dc::devices::v4l2 {

// What a V4L2 pixel format is good for in depthcloud.
enum class FormatRole {
    Depth, // 'Z16 ' (depth) and 'Y16 ' (16-bit grey that UVC depth modules and test drivers use for depth)
    Color, // YUYV, NV12, MJPEG, RGB24: the camera image
    Guide, // GREY: an infrared image, usable as the camera image (and so as the upsampling guide)
    Other,
};

FormatRole roleOf(std::uint32_t fourcc);
const char* toString(FormatRole role);
// "Z16 " for V4L2_PIX_FMT_Z16; non-printable bytes become '?'.
std::string fourccToString(std::uint32_t fourcc);
// "Z16", "z16 ", "YUYV", "MJPG"... (padded with spaces); nullopt when not 1-4 printable characters.
std::optional<std::uint32_t> parseFourcc(const std::string& text);

// The bytes one frame must at least hold: the image rows at `bytesPerLine` (NV12: plus the chroma rows).
// 0 for compressed formats, whose size varies per frame.
std::size_t minimumFrameBytes(std::uint32_t fourcc, int width, int height, std::uint32_t bytesPerLine);

// Converts a 'Z16 '/'Y16 ' buffer to meters once, at the device boundary: meters = raw * metersPerUnit in
// float, raw 0 (no measurement) stays 0. Rows are `bytesPerLine` apart (drivers may pad them). The caller
// has checked that `raw` holds minimumFrameBytes().
void depthToMeters(std::span<const std::uint8_t> raw, int width, int height, std::uint32_t bytesPerLine,
                   float metersPerUnit, frame::Plane<float>& out);

// Copies a color/guide buffer into an owned CapturedImage without row padding. MJPEG stays compressed
// (PixelFormat::Jpeg, its size checked); GREY becomes NV12 with neutral chroma, so the viewer shows it as a
// grey camera image.
Expected<frame::CapturedImage> toCapturedImage(std::uint32_t fourcc, std::span<const std::uint8_t> raw,
                                               int width, int height, std::uint32_t bytesPerLine);

} // namespace dc::devices::v4l2
