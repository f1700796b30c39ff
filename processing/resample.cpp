#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dc::processing {

cv::Mat resized(const cv::Mat& source, cv::Size size) {
    if (source.size() == size)
        return source;
    // Bilinear already reads every source pixel down to half the size; only beyond that it would skip some.
    const bool shrinks = 2 * size.width <= source.cols || 2 * size.height <= source.rows;
    cv::Mat current = source;
    // OpenCV's area resize has a fast path for exactly 2x only (4x is 8x slower per output pixel than two
    // 2x steps); halving an even size twice averages exactly the same pixels as one 4x step.
    while (shrinks && 2 * size.width <= current.cols && 2 * size.height <= current.rows &&
           current.cols % 2 == 0 && current.rows % 2 == 0) {
        cv::Mat half;
        cv::resize(current, half, {current.cols / 2, current.rows / 2}, 0, 0, cv::INTER_AREA);
        current = half;
    }
    if (current.size() == size)
        return current;
    cv::Mat out;
    cv::resize(current, out, size, 0, 0, shrinks ? cv::INTER_AREA : cv::INTER_LINEAR);
    return out;
}

BilinearTaps bilinearTaps(int sourceSize, int destinationSize) {
    BilinearTaps taps;
    const auto n = static_cast<std::size_t>(std::max(destinationSize, 0));
    taps.first.resize(n);
    taps.second.resize(n);
    taps.weight.resize(n);
    const double scale = static_cast<double>(sourceSize) / destinationSize;
    for (std::size_t d = 0; d < n; ++d) {
        const double s = std::clamp((static_cast<double>(d) + 0.5) * scale - 0.5, 0.0, sourceSize - 1.0);
        const int i = static_cast<int>(std::floor(s));
        taps.first[d] = i;
        taps.second[d] = std::min(i + 1, sourceSize - 1);
        taps.weight[d] = static_cast<float>(s - i);
    }
    return taps;
}

void mixRow(const std::uint8_t* __restrict src, float target, const float* __restrict t,
            std::uint8_t* __restrict dst, int n) {
    for (int x = 0; x < n; ++x) {
        const float v = static_cast<float>(src[x]) + (target - static_cast<float>(src[x])) * t[x];
        dst[x] = static_cast<std::uint8_t>(std::min(std::max(v, 0.0f), 255.0f) + 0.5f);
    }
}

void addRow(const std::uint8_t* __restrict src, const float* __restrict add, std::uint8_t* __restrict dst,
            int n) {
    for (int x = 0; x < n; ++x) {
        const float v = static_cast<float>(src[x]) + add[x];
        dst[x] = static_cast<std::uint8_t>(std::min(std::max(v, 0.0f), 255.0f) + 0.5f);
    }
}

std::array<cv::Mat, 3> rgbPlanes(const std::vector<std::uint8_t>& rgb, int width, int height) {
    std::array<cv::Mat, 3> planes;
    // cv::Mat wants a mutable pointer; split only reads it.
    cv::split(cv::Mat(height, width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data())), planes.data());
    return planes;
}

void mergeRgba(const std::uint8_t* r, const std::uint8_t* g, const std::uint8_t* b, std::uint8_t* rgba,
               int n) {
    const auto row = [n](const std::uint8_t* p) {
        return cv::Mat(1, n, CV_8U, const_cast<std::uint8_t*>(p));
    };
    const cv::Mat planes[] = {row(r), row(g), row(b), cv::Mat(1, n, CV_8U, cv::Scalar(255))};
    cv::Mat out(1, n, CV_8UC4, rgba);
    cv::merge(planes, 4, out);
}

RowSampler::RowSampler(const cv::Mat& source, int outputWidth, int outputHeight)
    : source_(source), x_(bilinearTaps(source.cols, outputWidth)),
      y_(bilinearTaps(source.rows, outputHeight)) {}

void RowSampler::sample(int y, float* row, std::vector<float>& scratch) const {
    scratch.resize(static_cast<std::size_t>(source_.cols));
    const float* r0 = source_.ptr<float>(y_.first[y]);
    const float* r1 = source_.ptr<float>(y_.second[y]);
    const float t = y_.weight[y];
    for (int x = 0; x < source_.cols; ++x)
        scratch[x] = r0[x] + t * (r1[x] - r0[x]);
    for (std::size_t x = 0; x < x_.first.size(); ++x) {
        const float v0 = scratch[x_.first[x]];
        row[x] = v0 + x_.weight[x] * (scratch[x_.second[x]] - v0);
    }
}

} // namespace dc::processing
