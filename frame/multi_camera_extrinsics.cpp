#include "frame/multi_camera_extrinsics.h"

#include "base/files.h"
#include "frame/calibration_fields.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <sstream>
#include <string_view>

namespace dc::frame {

namespace {

using fields::fieldError;

// R Rᵀ may differ from I by rounding in the file: calibration tools print 6 to 9 digits.
constexpr double kExtrinsicsRotationTolerance = 1e-4;
// More cameras than any rig has: a larger index is a typo, not a camera.
constexpr int kMaxRigCameras = 64;
constexpr std::string_view kKalibrPrefix = "cam";
constexpr std::string_view kOpenCvPrefix = "camera_";

// A 4x4 row-major matrix (a nested list, a flat one or an !!opencv-matrix) that must be rigid.
Expected<RigidTransform> rigidFromMatrix(const YAML::Node& node, const std::string& field,
                                         const std::string& origin) {
    auto t = fields::homogeneousMatrix(node, field, origin);
    if (t && !(rotationError(t->rotation) <= kExtrinsicsRotationTolerance))
        return fieldError(origin, field, "not rigid (the rotation is not orthonormal with determinant +1)");
    return t;
}

// N of a key "<prefix>N"; -1 for any other key.
int cameraIndexOf(const std::string& key, std::string_view prefix) {
    if (!key.starts_with(prefix) || key.size() == prefix.size() || key.size() > prefix.size() + 4)
        return -1;
    const std::string_view digits = std::string_view(key).substr(prefix.size());
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return -1;
    return std::stoi(std::string(digits));
}

// One more than the largest camera index among the root's keys.
int cameraKeyCount(const YAML::Node& root, std::string_view prefix) {
    int count = 0;
    for (const auto& entry : root)
        count = std::max(count, cameraIndexOf(fields::text(entry.first), prefix) + 1);
    return count;
}

Expected<CameraExtrinsicsSet> readKalibrChain(const YAML::Node& root, const std::string& origin) {
    const int count = cameraKeyCount(root, kKalibrPrefix);
    if (count > kMaxRigCameras)
        return fieldError(origin, "cam" + std::to_string(count - 1), "more cameras than a rig has (64)");
    CameraExtrinsicsSet set{{}, "Kalibr camchain"};
    RigidTransform toWorld; // cam0's frame is the world's
    for (int k = 0; k < count; ++k) {
        const std::string name = "cam" + std::to_string(k);
        if (!fields::child(root, name).IsMap())
            return fieldError(origin, name,
                              "missing (the chain goes on to cam" + std::to_string(count - 1) + ")");
        if (k > 0) {
            auto step = rigidFromMatrix(fields::child(fields::child(root, name), "T_cn_cnm1"),
                                        name + ".T_cn_cnm1", origin);
            if (!step)
                return step.error();
            // T_cn_cnm1 takes the previous camera's points to this one's: back to the previous, then to the
            // world.
            toWorld = compose(toWorld, inverse(*step));
        }
        set.cameras.push_back({name, toWorld});
    }
    return set;
}

Expected<CameraExtrinsicsSet> readOpenCvExtrinsics(const YAML::Node& root, const std::string& origin) {
    const std::optional<double> count = fields::number(fields::child(root, "camera_count"));
    if (!count || !(*count >= 1 && *count <= kMaxRigCameras) || *count != std::floor(*count))
        return fieldError(origin, "camera_count", "expected the number of cameras, 1 to 64");
    if (const int keys = cameraKeyCount(root, kOpenCvPrefix); keys > *count)
        return fieldError(origin, "camera_" + std::to_string(keys - 1),
                          "beyond camera_count " + fields::text(fields::child(root, "camera_count")));
    CameraExtrinsicsSet set{{}, "OpenCV extrinsics"};
    for (int i = 0; i < static_cast<int>(*count); ++i) {
        const std::string name = "camera_" + std::to_string(i);
        auto toWorld = rigidFromMatrix(fields::child(root, name), name, origin);
        if (!toWorld)
            return toWorld.error();
        set.cameras.push_back({name, *toWorld});
    }
    return set;
}

std::string chainRow(const RigidTransform& t, int row) {
    char text[160];
    std::snprintf(text, sizeof text, "  - [%.17g, %.17g, %.17g, %.17g]\n", t.rotation[3 * row],
                  t.rotation[3 * row + 1], t.rotation[3 * row + 2], t.translationMeters[row]);
    return text;
}

bool nearIdentity(const RigidTransform& t) {
    const RigidTransform identity;
    for (int i = 0; i < 9; ++i)
        if (!(std::abs(t.rotation[i] - identity.rotation[i]) <= 1e-9))
            return false;
    return std::all_of(t.translationMeters.begin(), t.translationMeters.end(),
                       [](double v) { return std::abs(v) <= 1e-9; });
}

Expected<std::string> writeKalibrChain(const CameraExtrinsicsSet& set) {
    if (!nearIdentity(set.cameras[0].cameraToWorld))
        return Error{"Kalibr's world is cam0's frame: the first camera (" + set.cameras[0].name +
                     ") must be at the identity"};
    std::ostringstream out;
    out << "# Extrinsics only: each camK's T_cn_cnm1 takes cam(K-1)'s points to camK's.\ncam0: {}\n";
    for (std::size_t k = 1; k < set.cameras.size(); ++k) {
        const RigidTransform step =
            compose(inverse(set.cameras[k].cameraToWorld), set.cameras[k - 1].cameraToWorld);
        out << "cam" << k << ":\n  T_cn_cnm1:\n";
        for (int row = 0; row < 3; ++row)
            out << chainRow(step, row);
        out << "  - [0, 0, 0, 1]\n";
    }
    return out.str();
}

std::string writeOpenCvExtrinsics(const CameraExtrinsicsSet& set) {
    cv::FileStorage fs("extrinsics.yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "camera_count" << static_cast<int>(set.cameras.size());
    for (std::size_t i = 0; i < set.cameras.size(); ++i) {
        const RigidTransform& t = set.cameras[i].cameraToWorld;
        const auto& r = t.rotation;
        const auto& p = t.translationMeters;
        fs << "camera_" + std::to_string(i)
           << (cv::Mat_<double>(4, 4) << r[0], r[1], r[2], p[0], r[3], r[4], r[5], p[1], r[6], r[7], r[8],
               p[2], 0.0, 0.0, 0.0, 1.0);
    }
    return fs.releaseAndGetString();
}

} // namespace

const CameraExtrinsics* CameraExtrinsicsSet::find(const std::string& name) const {
    const auto it = std::find_if(cameras.begin(), cameras.end(),
                                 [&](const CameraExtrinsics& c) { return c.name == name; });
    return it == cameras.end() ? nullptr : &*it;
}

Expected<CameraExtrinsicsSet> parseCameraExtrinsics(const std::string& text, const std::string& origin) {
    const auto root = fields::parseDocument(text, origin);
    if (!root)
        return root.error();
    if (fields::child(*root, "cam0").IsMap())
        return readKalibrChain(*root, origin);
    if (fields::has(*root, "camera_count"))
        return readOpenCvExtrinsics(*root, origin);
    return Error{origin + ": not a Kalibr camchain (cam0, cam1...) nor OpenCV extrinsics (camera_count, "
                          "camera_0...)"};
}

Expected<CameraExtrinsicsSet> loadCameraExtrinsics(const std::string& path) {
    auto bytes = base::readFile(path);
    if (!bytes)
        return bytes.error();
    return parseCameraExtrinsics(std::string(bytes->begin(), bytes->end()), path);
}

Expected<std::string> writeCameraExtrinsics(const CameraExtrinsicsSet& set, ExtrinsicsFormat format) {
    if (set.cameras.empty())
        return Error{"no cameras to write"};
    if (set.cameras.size() > static_cast<std::size_t>(kMaxRigCameras))
        return Error{"more cameras than a rig has (64)"};
    if (format == ExtrinsicsFormat::KalibrCamchain)
        return writeKalibrChain(set);
    return writeOpenCvExtrinsics(set);
}

} // namespace dc::frame
