#pragma once

#include "base/expected.h"
#include "frame/frame.h"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

// The text files of a TUM RGB-D sequence, parsed without touching the disk (the fuzz targets call these).
namespace dc::devices::replay {

struct TumListEntry {
    double timestampSeconds = 0.0;
    std::string file; // as written: relative to the sequence directory, or absolute
};

// rgb.txt / depth.txt: "timestamp filename" per line; '#' starts a comment line. Sorted by timestamp.
Expected<std::vector<TumListEntry>> parseTumList(std::string_view text, const std::string& file);

struct TumPose {
    double timestampSeconds = 0.0;
    frame::Pose pose; // camera-to-world of the color camera's optical centre
};

// groundtruth.txt: "timestamp tx ty tz qx qy qz qw" per line, '#' comments. Sorted by timestamp.
Expected<std::vector<TumPose>> parseTumGroundTruth(std::string_view text, const std::string& file);

// Pairs each a[i] with the b[j] nearest in time, one to one, as TUM's associate.py does: candidate pairs
// within maxDifference are taken greedily from the closest. Both inputs sorted; the result is sorted by i.
std::vector<std::pair<std::size_t, std::size_t>>
associateByTimestamp(const std::vector<double>& a, const std::vector<double>& b, double maxDifference);

} // namespace dc::devices::replay
