#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <vector>

namespace dc::tool {

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
