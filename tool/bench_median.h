#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

namespace dc::tool {

inline double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The middle and the tail of a benchmark's samples: the median (the mean of the middle two for an even
// count) and the nearest-rank 99th percentile. Zeros for no samples.
struct Spread {
    double median = 0.0;
    double p99 = 0.0;
};

inline Spread spreadOf(std::vector<double> samples) {
    if (samples.empty())
        return {};
    std::sort(samples.begin(), samples.end());
    const std::size_t n = samples.size();
    const double median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
    const auto p99 = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(n))) - 1;
    return {median, samples[std::min(p99, n - 1)]};
}

// The median wall time of `runs` timed calls work(i), after `warmups` untimed ones that warm caches,
// tables and allocations.
inline double medianMs(int runs, const std::function<void(int)>& work, int warmups = 1) {
    for (int i = 0; i < warmups; ++i)
        work(i);
    std::vector<double> ms;
    for (int i = 0; i < runs; ++i) {
        const auto start = std::chrono::steady_clock::now();
        work(i);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    const auto middle = ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2);
    std::nth_element(ms.begin(), middle, ms.end());
    return *middle;
}

} // namespace dc::tool
