#include "frame/calibration_fields.h"
#include "frame/calibration_formats.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

namespace dc::frame::formats {

namespace {

using fields::fieldError;

Expected<LensModel> lensModel(const YAML::Node& node, const std::string& field, const std::string& origin,
                              bool anyCoefficient) {
    if (!node.IsDefined())
        return anyCoefficient ? LensModel::BrownConrady : LensModel::None;
    const std::string name = fields::text(node);
    for (LensModel m : {LensModel::None, LensModel::BrownConrady, LensModel::InverseBrownConrady})
        if (name == toString(m))
            return m;
    return fieldError(origin, field,
                      "'" + name + "' is not a lens model (none, brown_conrady, inverse_brown_conrady)");
}

// Camera `index` (1: depth, 2: colour): K, D, its image size and lens model.
Expected<CameraModel> readCamera(const YAML::Node& root, int index, const std::string& origin,
                                 std::string& sizeField) {
    const std::string n = std::to_string(index);
    const fields::Named kNode = fields::firstOf(root, {"K" + n, "M" + n, "cameraMatrix" + n});
    auto k = fields::numbers(kNode.node, kNode.name, origin, 9);
    if (!k)
        return k.error();
    const fields::Named dNode = fields::firstOf(root, {"D" + n, "distCoeffs" + n});
    std::vector<double> d(5, 0.0);
    if (dNode.node.IsDefined()) {
        auto read = fields::numbers(dNode.node, dNode.name, origin);
        if (!read)
            return read.error();
        if (read->size() < 4 || std::any_of(read->begin() + std::min<std::ptrdiff_t>(5, std::ssize(*read)),
                                            read->end(), [](double c) { return c != 0.0; }))
            return fieldError(origin, dNode.name,
                              "expected k1 k2 p1 p2 [k3] (rational and thin-prism terms are not supported)");
        std::copy_n(read->begin(), std::min<std::size_t>(5, read->size()), d.begin());
    }
    const fields::Named sizeNode = fields::firstOf(root, {"image_size" + n, "imageSize" + n});
    sizeField = sizeNode.name;
    auto size = fields::imageSize(sizeNode.node, sizeNode.name, origin);
    if (!size)
        return size.error();
    const bool anyCoefficient = std::any_of(d.begin(), d.end(), [](double c) { return c != 0.0; });
    auto model = lensModel(fields::child(root, "lens_model" + n), "lens_model" + n, origin, anyCoefficient);
    if (!model)
        return model.error();
    CameraModel camera{{(*k)[0], (*k)[4], (*k)[2], (*k)[5], (*size)[0], (*size)[1]}, {*model, {}}};
    if (*model != LensModel::None)
        std::copy_n(d.begin(), 5, camera.lens.coefficients.begin());
    if (Status s = fields::checkIntrinsics(camera.intrinsics, kNode.name, origin); !s)
        return s.error();
    return camera;
}

cv::Mat matrixOf(const double* values, int rows, int cols) {
    return cv::Mat(rows, cols, CV_64F, const_cast<double*>(values)).clone();
}

void writeCamera(cv::FileStorage& fs, const CameraModel& camera, int index) {
    const std::string n = std::to_string(index);
    const Intrinsics& k = camera.intrinsics;
    const double matrix[9] = {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0};
    fs << "image_size" + n << std::vector<int>{k.width, k.height};
    fs << "K" + n << matrixOf(matrix, 3, 3);
    fs << "D" + n << matrixOf(camera.lens.coefficients.data(), 1, 5);
    fs << "lens_model" + n << toString(camera.lens.model);
}

} // namespace

// Any of a stereo file's own fields makes it one, so that a missing one is named rather than the file
// being taken for a single camera's.
bool isOpenCvStereo(const YAML::Node& root) {
    for (const char* name : {"R", "T", "K1", "M1", "cameraMatrix1", "K2", "M2", "cameraMatrix2"})
        if (fields::has(root, name))
            return true;
    return false;
}

Expected<Calibration> readOpenCvStereo(const YAML::Node& root, const std::string& origin, bool json) {
    Calibration result;
    result.format = json ? "OpenCV stereo JSON" : "OpenCV stereo YAML";
    RigCalibration rig;
    auto depth = readCamera(root, 1, origin, result.depthSizeField);
    if (!depth)
        return depth.error();
    auto colour = readCamera(root, 2, origin, result.colourSizeField);
    if (!colour)
        return colour.error();
    auto r = fields::numbers(fields::child(root, "R"), "R", origin, 9);
    if (!r)
        return r.error();
    auto t = fields::numbers(fields::child(root, "T"), "T", origin, 3);
    if (!t)
        return t.error();
    rig.depth = *depth;
    rig.colour = *colour;
    std::copy_n(r->begin(), 9, rig.depthToColour.rotation.begin());
    std::copy_n(t->begin(), 3, rig.depthToColour.translationMeters.begin());
    if (Status s = fields::checkTransform(rig.depthToColour, "R", "T", origin); !s)
        return s.error();
    rig.name = origin + " (" + result.format + ")";
    result.intrinsics = rig.colour.intrinsics;
    result.rig = std::move(rig);
    return result;
}

Expected<std::string> writeOpenCvStereo(const RigCalibration& rig, bool json) {
    cv::FileStorage fs(json ? "calibration.json" : "calibration.yml",
                       cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    writeCamera(fs, rig.depth, 1);
    writeCamera(fs, rig.colour, 2);
    fs << "R" << matrixOf(rig.depthToColour.rotation.data(), 3, 3);
    fs << "T" << matrixOf(rig.depthToColour.translationMeters.data(), 3, 1);
    return fs.releaseAndGetString();
}

} // namespace dc::frame::formats
