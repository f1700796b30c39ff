#include "frame/calibration.h"

#include "frame/calibration_fields.h"
#include "frame/calibration_formats.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <opencv2/core.hpp>
#include <sstream>
#include <vector>

namespace dc::frame {

namespace {

cv::FileNode cameraMatrixNode(const cv::FileStorage& fs) {
    for (const char* name : {"camera_matrix", "cameraMatrix", "K"}) {
        cv::FileNode node = fs[name];
        if (!node.empty())
            return node;
    }
    return {};
}

Expected<Calibration> readCalibration(const cv::FileStorage& fs, const std::string& origin) {
    const cv::FileNode matrix = cameraMatrixNode(fs);
    if (matrix.empty() || !matrix.isMap())
        return Error{origin + ": no camera_matrix (expected OpenCV or ROS camera_info calibration YAML)"};
    std::vector<double> k;
    matrix["data"] >> k;
    if (k.size() != 9)
        return Error{origin + ": camera_matrix must hold 9 values (3x3), found " + std::to_string(k.size())};
    Calibration result;
    result.format =
        fs["distortion_model"].empty() && fs["camera_name"].empty() ? "OpenCV YAML" : "ROS camera_info YAML";
    result.intrinsics = {
        k[0], k[4], k[2], k[5], static_cast<int>(fs["image_width"]), static_cast<int>(fs["image_height"])};
    if (!result.intrinsics.valid())
        return Error{origin + ": calibration needs image_width, image_height and positive focal lengths"};
    return result;
}

// YAML lets a block sequence under a key start at the key's own indentation ("T_cn_cnm1:\n- [...]"), as
// Kalibr writes it; FileStorage's parser wants it indented deeper, so such items move two spaces in.
std::string indentCompactSequences(const std::string& text) {
    std::istringstream in(text);
    std::string out, line;
    std::size_t keyIndent = std::string::npos; // of the last key with nothing after its colon
    while (std::getline(in, line)) {
        const std::size_t indent = line.find_first_not_of(' ');
        const bool item = indent != std::string::npos && line.compare(indent, 2, "- ") == 0;
        out += (item && indent == keyIndent ? "  " : "") + line + "\n";
        const std::size_t last = line.find_last_not_of(" \r");
        if (!item && indent != std::string::npos)
            keyIndent = line[last] == ':' ? indent : std::string::npos;
    }
    return out;
}

} // namespace

Expected<Calibration> parseCalibration(const std::string& text, const std::string& origin) {
    const bool json = text.find_first_not_of(" \t\r\n") != std::string::npos &&
                      text[text.find_first_not_of(" \t\r\n")] == '{';
    // ROS camera_info and Kalibr files are plain YAML without OpenCV's "%YAML:1.0" header, which
    // FileStorage needs to read YAML from memory.
    const std::string yaml = json ? text : indentCompactSequences(text);
    const std::string content = json || text.rfind("%YAML", 0) == 0 ? yaml : "%YAML:1.0\n---\n" + yaml;
    try {
        const cv::FileStorage fs(content, cv::FileStorage::READ | cv::FileStorage::MEMORY);
        if (!fs.isOpened())
            return Error{origin + ": not a YAML or JSON calibration file"};
        if (formats::isKalibr(fs))
            return formats::readKalibr(fs, origin);
        if (formats::isOpenCvStereo(fs))
            return formats::readOpenCvStereo(fs, origin, json);
        return readCalibration(fs, origin);
    } catch (const cv::Exception&) {
        return Error{origin + ": malformed calibration YAML or JSON"};
    }
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
