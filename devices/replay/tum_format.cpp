#include "devices/replay/tum_format.h"

#include "devices/replay/replay_source.h"
#include "devices/replay/text_fields.h"

#include <algorithm>
#include <cmath>
#include <compare>
#include <optional>
#include <queue>

namespace dc::devices::replay {

namespace {

// Calls parse(fields, line, problem) for every line that is neither blank nor a '#' comment.
template <class Parse> std::string forEachRecord(std::string_view text, Parse parse) {
    std::string problem;
    forEachLine(text, [&](const TextLine& line) {
        const std::string_view content = trim(line.text);
        if (content.empty() || content.front() == '#')
            return true;
        return parse(splitFields(content, 0), line, problem);
    });
    return problem;
}

template <class T> void sortByTime(std::vector<T>& v) {
    std::stable_sort(v.begin(), v.end(),
                     [](const T& a, const T& b) { return a.timestampSeconds < b.timestampSeconds; });
}

struct Candidate {
    double difference;
    std::size_t i, j;
    auto operator<=>(const Candidate&) const = default;
};

// Indices 0..n-1, some taken: the nearest free one at or after / before an index, in near-constant time
// (two union-find forests with path halving).
class UnusedIndices {
public:
    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

    explicit UnusedIndices(std::size_t n) : after_(n + 1), before_(n + 1), taken_(n) {
        for (std::size_t k = 0; k <= n; ++k)
            after_[k] = before_[k] = k;
    }
    bool taken(std::size_t j) const { return taken_[j]; }
    void take(std::size_t j) {
        taken_[j] = true;
        after_[j] = j + 1;
        before_[j + 1] = j;
    }
    // The first free index >= j, or n.
    std::size_t next(std::size_t j) { return root(after_, j); }
    // The last free index < j, or kNone.
    std::size_t previous(std::size_t j) { return root(before_, j) == 0 ? kNone : root(before_, j) - 1; }

private:
    static std::size_t root(std::vector<std::size_t>& parent, std::size_t k) {
        while (parent[k] != k)
            k = parent[k] = parent[parent[k]];
        return k;
    }
    std::vector<std::size_t> after_;  // after_[k] == k: k is free (or k == n)
    std::vector<std::size_t> before_; // before_[k] == k: k - 1 is free (or k == 0)
    std::vector<bool> taken_;
};

} // namespace

Expected<std::vector<TumListEntry>> parseTumList(std::string_view text, const std::string& file) {
    std::vector<TumListEntry> entries;
    const std::string problem =
        forEachRecord(text, [&](const auto& fields, const TextLine& line, std::string& p) {
            double t = 0.0;
            if (fields.size() < 2 || !parseFiniteDouble(fields[0], t)) {
                p = linePrefix(file, line) + "expected 'timestamp filename'";
                return false;
            }
            entries.push_back({t, std::string(fields[1])});
            return true;
        });
    if (!problem.empty())
        return Error{problem};
    sortByTime(entries);
    return entries;
}

Expected<std::vector<TumPose>> parseTumGroundTruth(std::string_view text, const std::string& file) {
    std::vector<TumPose> poses;
    const std::string problem =
        forEachRecord(text, [&](const auto& fields, const TextLine& line, std::string& p) {
            double v[8] = {};
            bool ok = fields.size() >= 8;
            for (std::size_t i = 0; ok && i < 8; ++i)
                ok = parseFiniteDouble(fields[i], v[i]);
            if (!ok || std::abs(v[4]) + std::abs(v[5]) + std::abs(v[6]) + std::abs(v[7]) == 0.0) {
                p = linePrefix(file, line) +
                    "expected 'timestamp tx ty tz qx qy qz qw' with a non-zero quaternion";
                return false;
            }
            poses.push_back({v[0], poseFromQuaternion(v + 1, v + 4)});
            return true;
        });
    if (!problem.empty())
        return Error{problem};
    sortByTime(poses);
    return poses;
}

std::vector<std::pair<std::size_t, std::size_t>>
associateByTimestamp(const std::vector<double>& a, const std::vector<double>& b, double maxDifference) {
    // The greedy matching over every candidate pair in order of (difference, i, j), done lazily: each a[i]
    // keeps one entry, its nearest b not yet taken, so a list of many equal stamps costs O(n log n) instead
    // of a candidate per pair (a 64 KB list of equal stamps needed gigabytes).
    UnusedIndices unused(b.size());
    const auto nearest = [&](std::size_t i) -> std::optional<Candidate> {
        const double t = a[i];
        const auto inWindow = [&](std::size_t j) {
            return b[j] >= t - maxDifference && b[j] <= t + maxDifference;
        };
        const auto split = static_cast<std::size_t>(std::lower_bound(b.begin(), b.end(), t) - b.begin());
        std::optional<Candidate> best;
        if (const std::size_t back = unused.previous(split); back != UnusedIndices::kNone && inWindow(back)) {
            // Of equal earlier stamps the lowest index comes first, as in a stable sort of all pairs.
            const auto first =
                static_cast<std::size_t>(std::lower_bound(b.begin(), b.end(), b[back]) - b.begin());
            best = Candidate{std::abs(t - b[back]), i, unused.next(first)};
        }
        if (const std::size_t ahead = unused.next(split); ahead < b.size() && inWindow(ahead)) {
            const Candidate c{std::abs(t - b[ahead]), i, ahead};
            if (!best || c.difference < best->difference)
                best = c;
        }
        return best;
    };
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (auto c = nearest(i))
            queue.push(*c);
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    while (!queue.empty()) {
        const Candidate c = queue.top();
        queue.pop();
        if (unused.taken(c.j)) {
            if (auto again = nearest(c.i))
                queue.push(*again);
            continue;
        }
        unused.take(c.j);
        pairs.emplace_back(c.i, c.j);
    }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

} // namespace dc::devices::replay
