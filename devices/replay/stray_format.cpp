#include "devices/replay/stray_format.h"

#include "devices/replay/replay_source.h"
#include "devices/replay/text_fields.h"

#include <cmath>

namespace dc::devices::replay {

Expected<frame::Intrinsics> parseStrayCameraMatrix(std::string_view text, const std::string& file) {
    std::vector<double> values;
    std::string problem;
    forEachLine(text, [&](const TextLine& line) {
        if (trim(line.text).empty())
            return true;
        const auto fields = splitFields(line.text, ',');
        if (fields.size() != 3 || values.size() >= 9) {
            problem = linePrefix(file, line) + "expected three comma-separated numbers per row, three rows";
            return false;
        }
        for (const std::string_view f : fields) {
            double v = 0.0;
            if (!parseFiniteDouble(f, v)) {
                problem = linePrefix(file, line) + "'" + std::string(f) + "' is not a number";
                return false;
            }
            values.push_back(v);
        }
        return true;
    });
    if (!problem.empty())
        return Error{problem};
    if (values.size() != 9)
        return Error{file + ": expected a 3x3 camera matrix, found " + std::to_string(values.size()) +
                     " numbers"};
    frame::Intrinsics k{values[0], values[4], values[2], values[5], 0, 0};
    if (!(k.fx > 0.0 && k.fy > 0.0))
        return Error{file + ": the camera matrix has non-positive focal lengths (fx " + std::to_string(k.fx) +
                     ", fy " + std::to_string(k.fy) + ")"};
    return k;
}

Expected<std::vector<StrayOdometryRow>> parseStrayOdometry(std::string_view text, const std::string& file) {
    std::vector<StrayOdometryRow> rows;
    std::string problem;
    forEachLine(text, [&](const TextLine& line) {
        const std::string_view content = trim(line.text);
        if (content.empty() || (rows.empty() && line.number == 1 && content.starts_with("timestamp")))
            return true;
        const auto fields = splitFields(content, ',');
        double v[9] = {};
        if (fields.size() < 9) {
            problem = linePrefix(file, line) +
                      "expected at least 9 fields (timestamp, frame, x, y, z, qx, qy, "
                      "qz, qw), found " +
                      std::to_string(fields.size());
            return false;
        }
        for (std::size_t i = 0; i < 9; ++i) {
            if (!parseFiniteDouble(fields[i], v[i])) {
                problem = linePrefix(file, line) + "field " + std::to_string(i + 1) + " ('" +
                          std::string(fields[i]) + "') is not a finite number";
                return false;
            }
        }
        if (std::abs(v[5]) + std::abs(v[6]) + std::abs(v[7]) + std::abs(v[8]) == 0.0) {
            problem = linePrefix(file, line) + "the orientation quaternion is zero";
            return false;
        }
        rows.push_back({v[0], poseFromQuaternion(v + 2, v + 5)});
        return true;
    });
    if (!problem.empty())
        return Error{problem};
    return rows;
}

} // namespace dc::devices::replay
