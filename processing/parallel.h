#pragma once

#include <functional>

namespace dc::processing {

// Runs body(begin, end) over consecutive pieces of [0, count) on OpenCV's thread pool and returns when all
// are done. Ranges shorter than 2 * minPerPiece run inline: handing work to another thread costs more than
// it saves on a few rows.
void parallelRanges(int count, int minPerPiece, const std::function<void(int begin, int end)>& body);

} // namespace dc::processing
