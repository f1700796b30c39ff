#include "frame/calibration.h"

#include "frame/calibration_fields.h"
#include "frame/calibration_formats.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <opencv2/core.hpp>
#include <optional>
#include <sstream>
#include <vector>

namespace dc::frame {

namespace {

// An image side beyond this is not a camera's; refusing it keeps the conversion to int defined.
constexpr double kMaxImageSidePixels = 65535.0;

// image_width or image_height; 0, which Intrinsics::valid() refuses, when absent or not a number. A real is
// rounded to the nearest pixel, as OpenCV's own reader of these files does.
int imageSide(const YAML::Node& root, const std::string& name) {
    const std::optional<double> value = fields::number(fields::child(root, name));
    return value && *value >= 0.0 && *value <= kMaxImageSidePixels ? static_cast<int>(std::lround(*value))
                                                                   : 0;
}

Expected<Calibration> readCalibration(const YAML::Node& root, const std::string& origin) {
    const fields::Named matrix = fields::firstOf(root, {"camera_matrix", "cameraMatrix", "K"});
    if (!matrix.node.IsMap())
        return Error{origin + ": no camera_matrix (expected OpenCV or ROS camera_info calibration YAML)"};
    std::vector<double> k;
    if (const YAML::Node data = fields::child(matrix.node, "data"); data.IsDefined()) {
        auto read = fields::numbers(data, matrix.name, origin);
        if (!read)
            return read.error();
        k = std::move(*read);
    }
    if (k.size() != 9)
        return Error{origin + ": " + matrix.name + " must hold 9 values (3x3), found " +
                     std::to_string(k.size())};
    Calibration result;
    result.format = fields::has(root, "distortion_model") || fields::has(root, "camera_name")
                        ? "ROS camera_info YAML"
                        : "OpenCV YAML";
    result.intrinsics = {
        k[0], k[4], k[2], k[5], imageSide(root, "image_width"), imageSide(root, "image_height")};
    if (!result.intrinsics.valid())
        return Error{origin + ": calibration needs image_width, image_height and positive focal lengths"};
    return result;
}

} // namespace

// Every format is read by one YAML parser: JSON is YAML's flow style, and Kalibr's block sequences at their
// key's own indentation are plain YAML, so no format is rewritten before it is read.
Expected<Calibration> parseCalibration(const std::string& text, const std::string& origin) {
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    const bool json = first != std::string::npos && text[first] == '{';
    const auto root = fields::parseDocument(text, origin);
    if (!root)
        return root.error();
    if (!root->IsMap())
        return Error{origin + ": not a YAML or JSON calibration file"};
    if (formats::isKalibr(*root))
        return formats::readKalibr(*root, origin);
    if (formats::isOpenCvStereo(*root))
        return formats::readOpenCvStereo(*root, origin, json);
    return readCalibration(*root, origin);
}

Expected<Calibration> loadCalibration(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        return Error{"cannot read calibration file " + path};
    std::ostringstream text;
    text << in.rdbuf();
    return parseCalibration(text.str(), path);
}

namespace {

cv::Mat cameraMatrixOf(const Intrinsics& k) {
    return (cv::Mat_<double>(3, 3) << k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0);
}

std::string writeSingle(const Intrinsics& k, CalibrationFormat format) {
    cv::FileStorage fs("calibration.yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "image_width" << k.width << "image_height" << k.height;
    if (format == CalibrationFormat::RosCameraInfo) {
        fs << "camera_name"
           << "depthcloud";
        fs << "camera_matrix"
           << "{"
           << "rows" << 3 << "cols" << 3 << "data"
           << std::vector<double>{k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0} << "}";
        fs << "distortion_model"
           << "plumb_bob";
    } else {
        fs << "camera_matrix" << cameraMatrixOf(k);
    }
    return fs.releaseAndGetString();
}

bool sameShape(int calibratedWidth, int calibratedHeight, int width, int height) {
    // Scaled evenly, to within the rounding of an odd size.
    const double sx = static_cast<double>(width) / calibratedWidth,
                 sy = static_cast<double>(height) / calibratedHeight;
    return std::abs(sx - sy) <= 1.0 / std::min(calibratedWidth, calibratedHeight) + 1e-9;
}

Status checkSize(const Intrinsics& k, int width, int height, const std::string& field, const char* stream) {
    if (width <= 0 || height <= 0 || sameShape(k.width, k.height, width, height))
        return {};
    return Error{"calibration " + field + " " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                 " does not fit the " + stream + " stream's " + std::to_string(width) + "x" +
                 std::to_string(height)};
}

} // namespace

Expected<std::string> writeCalibration(const Calibration& calibration, CalibrationFormat format) {
    switch (format) {
    case CalibrationFormat::OpenCvYaml:
    case CalibrationFormat::RosCameraInfo:
        return writeSingle(calibration.intrinsics, format);
    case CalibrationFormat::OpenCvStereoYaml:
    case CalibrationFormat::OpenCvStereoJson:
    case CalibrationFormat::KalibrCamchain:
        break;
    }
    if (!calibration.rig)
        return Error{"a two-sensor format needs a two-sensor calibration"};
    if (format == CalibrationFormat::KalibrCamchain)
        return formats::writeKalibr(*calibration.rig);
    return formats::writeOpenCvStereo(*calibration.rig, format == CalibrationFormat::OpenCvStereoJson);
}

Status checkStreamSizes(const Calibration& calibration, int depthWidth, int depthHeight, int colourWidth,
                        int colourHeight) {
    if (!calibration.rig)
        return {};
    if (Status s = checkSize(calibration.rig->depth.intrinsics, depthWidth, depthHeight,
                             calibration.depthSizeField, "depth");
        !s)
        return s;
    return checkSize(calibration.rig->colour.intrinsics, colourWidth, colourHeight,
                     calibration.colourSizeField, "colour");
}

Intrinsics intrinsicsFromFieldOfView(int width, int height, double horizontalFovDegrees) {
    const double halfFov = horizontalFovDegrees * std::numbers::pi / 360.0;
    const double f = 0.5 * width / std::tan(halfFov);
    return {f, f, 0.5 * width, 0.5 * height, width, height};
}

} // namespace dc::frame
