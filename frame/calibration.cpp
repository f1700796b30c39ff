#include "frame/calibration.h"

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

} // namespace

Expected<Calibration> parseCalibration(const std::string& text, const std::string& origin) {
    // ROS camera_info files are plain YAML without OpenCV's "%YAML:1.0" header, which FileStorage needs.
    const std::string yaml = text.rfind("%YAML", 0) == 0 ? text : "%YAML:1.0\n---\n" + text;
    try {
        const cv::FileStorage fs(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
        if (!fs.isOpened())
            return Error{origin + ": not a YAML calibration file"};
        return readCalibration(fs, origin);
    } catch (const cv::Exception&) {
        return Error{origin + ": malformed calibration YAML"};
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

Intrinsics intrinsicsFromFieldOfView(int width, int height, double horizontalFovDegrees) {
    const double halfFov = horizontalFovDegrees * std::numbers::pi / 360.0;
    const double f = 0.5 * width / std::tan(halfFov);
    return {f, f, 0.5 * width, 0.5 * height, width, height};
}

} // namespace dc::frame
