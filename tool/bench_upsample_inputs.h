#pragma once

// What `bench upsample`'s methods and its OpenCV peers (a module of their own) both feed their filters.

#include "tool/bench_upsample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dc::tool::upsample {

inline cv::Mat asMat(const frame::Plane<float>& p) {
    return {p.height, p.width, CV_32F, const_cast<float*>(p.pixels.data())};
}

inline frame::Plane<float> toPlane(const cv::Mat& m) {
    frame::Plane<float> p(m.cols, m.rows);
    m.convertTo(cv::Mat(p.height, p.width, CV_32F, p.pixels.data()), CV_32F);
    return p;
}

inline cv::Size outputSize(const Problem& p) {
    return {p.truth.width, p.truth.height};
}

// The guide at the output size, in a matrix kept from one call to the next as a loop over frames keeps it.
inline const cv::Mat& guideAtOutput(const cv::Mat& guide, cv::Size size) {
    if (guide.size() == size)
        return guide;
    thread_local cv::Mat out;
    cv::resize(guide, out, size, 0, 0, cv::INTER_AREA);
    return out;
}

// Parameters follow the upsampling factor f with one rule per method for every scene and factor: the best
// rule (by mean MAD over the Middlebury scenes at x2..x16) of a small sweep done while writing this bench.
inline int radiusFor(double factor, double base, double perFactor) {
    return std::max(1, static_cast<int>(std::lround(base + perFactor * factor)));
}

} // namespace dc::tool::upsample
