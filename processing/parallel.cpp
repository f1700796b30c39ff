#include "processing/parallel.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <thread>
#include <vector>

namespace dc::processing {

namespace {

#if defined(__SANITIZE_THREAD__)
// OpenCV's thread pool (TBB) is not instrumented: ThreadSanitizer cannot see its hand-offs and reports each
// as a race. Under TSan, OpenCV runs on the calling thread, and parallelRanges on threads of its own, whose
// start and join TSan sees, so that our pieces are still checked against each other.
[[maybe_unused]] const bool kOpenCvSequential = [] {
    cv::setNumThreads(0);
    return true;
}();
constexpr int kThreads = 2;

template <class Piece> void runPieces(int pieces, const Piece& piece) {
    std::vector<std::thread> threads;
    for (int p = 1; p < pieces; ++p)
        threads.emplace_back([&piece, p] { piece(p); });
    piece(0);
    for (std::thread& t : threads)
        t.join();
}
#else
int threadCount() {
    return std::max(cv::getNumThreads(), 1);
}

template <class Piece> void runPieces(int pieces, const Piece& piece) {
    cv::parallel_for_(
        cv::Range(0, pieces),
        [&](const cv::Range& range) {
            for (int p = range.start; p < range.end; ++p)
                piece(p);
        },
        pieces);
}
#endif

} // namespace

void parallelRanges(int count, int minPerPiece, const std::function<void(int begin, int end)>& body) {
    if (count <= 0)
        return;
#if defined(__SANITIZE_THREAD__)
    const int threads = kThreads;
#else
    const int threads = threadCount();
#endif
    // Two pieces per thread lets the pool balance a piece that another process delays.
    const int pieces = std::min(count / std::max(minPerPiece, 1), 2 * threads);
    if (pieces < 2) {
        body(0, count);
        return;
    }
    runPieces(pieces, [&](int piece) {
        body(static_cast<int>(static_cast<long long>(count) * piece / pieces),
             static_cast<int>(static_cast<long long>(count) * (piece + 1) / pieces));
    });
}

} // namespace dc::processing
