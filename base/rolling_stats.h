#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace dc::base {

// The last `capacity` samples of a measurement (a stage's milliseconds, say), for the median and maximum
// the status line and summaries report. Medians, because one slow frame should not move the figure.
class RollingStats {
public:
    explicit RollingStats(std::size_t capacity = 240) : capacity_(capacity) { samples_.reserve(capacity); }

    void add(double value) {
        if (samples_.size() < capacity_)
            samples_.push_back(value);
        else
            samples_[next_] = value;
        next_ = (next_ + 1) % capacity_;
    }

    std::size_t count() const { return samples_.size(); }

    // The samples oldest first, for plotting.
    std::vector<double> inOrder() const {
        if (samples_.size() < capacity_)
            return samples_;
        const auto split = samples_.begin() + static_cast<std::ptrdiff_t>(next_);
        std::vector<double> out(split, samples_.end());
        out.insert(out.end(), samples_.begin(), split);
        return out;
    }

    double median() const {
        if (samples_.empty())
            return 0.0;
        std::vector<double> sorted = samples_;
        const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
        std::nth_element(sorted.begin(), mid, sorted.end());
        if (sorted.size() % 2 == 1)
            return *mid;
        return 0.5 * (*mid + *std::max_element(sorted.begin(), mid));
    }

    double max() const {
        return samples_.empty() ? 0.0 : *std::max_element(samples_.begin(), samples_.end());
    }

private:
    std::size_t capacity_;
    std::size_t next_ = 0;
    std::vector<double> samples_;
};

} // namespace dc::base
