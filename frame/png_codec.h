#pragma once

#include "base/expected.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

// PNG to and from memory with libpng, so that the shipped binary needs neither opencv_imgcodecs nor what it
// links (GDAL, OpenEXR, ...). Channels are in PNG's order (gray, gray + alpha, RGB, RGBA), not OpenCV's BGR;
// 16-bit samples are native-endian in memory (PNG stores them big-endian).
namespace dc::frame {

enum class PngPixels {
    AsStored, // 8 or 16 bits, the file's channels (a palette becomes RGB, or RGBA with transparency)
    Rgb8,     // 8-bit RGB whatever the file holds: gray is repeated, alpha dropped, 16 bits scaled to 8
};

// Decodes a whole PNG (interlaced or not). Malformed, truncated or absurdly large data is an error, never
// a partial image.
Expected<cv::Mat> decodePng(std::span<const std::uint8_t> png, PngPixels pixels = PngPixels::AsStored);
// Reads and decodes a PNG file; an error names the file.
Expected<cv::Mat> readPng(const std::string& path, PngPixels pixels = PngPixels::AsStored);

// Encodes 8-bit gray, RGB or RGBA (CV_8UC1/3/4) or 16-bit gray (CV_16UC1) at a zlib compression level
// (0 none ... 9 smallest).
Expected<std::vector<std::uint8_t>> encodePng(const cv::Mat& image, int compressionLevel);
// Encodes and writes a PNG atomically (base::writeFileAtomically); an error names the file.
Status writePng(const std::string& path, const cv::Mat& image, int compressionLevel);

// Whether bytes start with PNG's signature.
bool looksLikePng(std::span<const std::uint8_t> bytes);

} // namespace dc::frame
