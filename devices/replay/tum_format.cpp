#include "devices/replay/tum_format.h"

#include "devices/replay/replay_source.h"
#include "devices/replay/text_fields.h"

#include <algorithm>
#include <cmath>

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
    struct Candidate {
        double difference;
        std::size_t i, j;
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < a.size(); ++i) {
        auto j =
            static_cast<std::size_t>(std::lower_bound(b.begin(), b.end(), a[i] - maxDifference) - b.begin());
        for (; j < b.size() && b[j] <= a[i] + maxDifference; ++j)
            candidates.push_back({std::abs(a[i] - b[j]), i, j});
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& x, const Candidate& y) { return x.difference < y.difference; });
    std::vector<bool> usedA(a.size()), usedB(b.size());
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (const Candidate& c : candidates) {
        if (usedA[c.i] || usedB[c.j])
            continue;
        usedA[c.i] = usedB[c.j] = true;
        pairs.emplace_back(c.i, c.j);
    }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

} // namespace dc::devices::replay
