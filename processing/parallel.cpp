#include "processing/parallel.h"

#include <opencv2/core.hpp>

#include <algorithm>

namespace dc::processing {

void parallelRanges(int count, int minPerPiece, const std::function<void(int begin, int end)>& body) {
    if (count <= 0)
        return;
    // Two pieces per thread lets the pool balance a piece that another process delays.
    const int pieces = std::min(count / std::max(minPerPiece, 1), 2 * std::max(cv::getNumThreads(), 1));
    if (pieces < 2) {
        body(0, count);
        return;
    }
    cv::parallel_for_(
        cv::Range(0, pieces),
        [&](const cv::Range& range) {
            for (int piece = range.start; piece < range.end; ++piece)
                body(static_cast<int>(static_cast<long long>(count) * piece / pieces),
                     static_cast<int>(static_cast<long long>(count) * (piece + 1) / pieces));
        },
        pieces);
}

} // namespace dc::processing
