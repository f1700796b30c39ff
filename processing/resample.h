#pragma once

// OpenCV glue shared by the processing kernels; include only from processing/*.cpp.

#include "devices/frame.h"

#include <opencv2/core.hpp>

#include <vector>

namespace dc::processing {

// A cv::Mat header over a plane's pixels (no copy). The const overload must only be read through.
inline cv::Mat asMat(devices::Plane<float>& plane) {
    return {plane.height, plane.width, CV_32F, plane.pixels.data()};
}
inline cv::Mat asMat(const devices::Plane<float>& plane) {
    return {plane.height, plane.width, CV_32F, const_cast<float*>(plane.pixels.data())};
}
inline cv::Mat asMat(const devices::Plane<std::uint8_t>& plane) {
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

} // namespace dc::processing
