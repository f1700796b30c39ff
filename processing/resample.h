#pragma once

// OpenCV glue shared by the processing kernels; include only from processing/*.cpp.

#include "frame/frame.h"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace dc::processing {

// A cv::Mat header over a plane's pixels (no copy). The const overload must only be read through.
inline cv::Mat asMat(frame::Plane<float>& plane) {
    return {plane.height, plane.width, CV_32F, plane.pixels.data()};
}
inline cv::Mat asMat(const frame::Plane<float>& plane) {
    return {plane.height, plane.width, CV_32F, const_cast<float*>(plane.pixels.data())};
}
inline cv::Mat asMat(const frame::Plane<std::uint8_t>& plane) {
    return {plane.height, plane.width, CV_8U, const_cast<std::uint8_t*>(plane.pixels.data())};
}

// `source` at `size`: area-averaged where it shrinks to half or less (no aliasing of noise or texture),
// bilinear with aligned pixel centres otherwise; `source` itself when the size already matches.
cv::Mat resized(const cv::Mat& source, cv::Size size);

// Where each pixel of a destination axis samples a source axis bilinearly, with OpenCV's INTER_LINEAR
// convention (pixel centres aligned, clamped at the border): value = (1 - w) * s[first] + w * s[second].
struct BilinearTaps {
    std::vector<int> first;
    std::vector<int> second;
    std::vector<float> weight;
};
BilinearTaps bilinearTaps(int sourceSize, int destinationSize);

// Per-row colour arithmetic on 8-bit planes, written so that the compiler vectorises it (restrict, no
// branches): dst = src + (target - src) * t, and dst = min(src + add, 255), rounded.
void mixRow(const std::uint8_t* __restrict src, float target, const float* __restrict t,
            std::uint8_t* __restrict dst, int n);
void addRow(const std::uint8_t* __restrict src, const float* __restrict add, std::uint8_t* __restrict dst,
            int n);

// Packed RGB as three planes, and three planes (plus opaque alpha) back into one RGBA row.
std::array<cv::Mat, 3> rgbPlanes(const std::vector<std::uint8_t>& rgb, int width, int height);
void mergeRgba(const std::uint8_t* r, const std::uint8_t* g, const std::uint8_t* b, std::uint8_t* rgba,
               int n);

// Bilinear samples of a small CV_32F image along the rows of a larger output, one row at a time, so that a
// per-pixel loop can use them without an output-sized temporary.
class RowSampler {
public:
    RowSampler(const cv::Mat& source, int outputWidth, int outputHeight);
    // `row` (outputWidth values) = the source sampled along output row y; `scratch` is the caller's buffer.
    void sample(int y, float* row, std::vector<float>& scratch) const;

private:
    cv::Mat source_;
    BilinearTaps x_, y_;
};

} // namespace dc::processing
