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
    cv::Mat out;
    cv::resize(source, out, size, 0, 0, shrinks ? cv::INTER_AREA : cv::INTER_LINEAR);
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

} // namespace dc::processing
