#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"

#include <initializer_list>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

// What the calibration readers share: fields read as numbers, and checks that name the field at fault.
namespace dc::frame::fields {

// The first of `names` present in `parent`, with the name it was found under (the first name if none).
struct Named {
    cv::FileNode node;
    std::string name;
};
Named firstOf(const cv::FileNode& parent, std::initializer_list<const char*> names);

// The numbers of a field: a number, a sequence (nested sequences flattened, row by row) or a matrix map
// with `data` (OpenCV's !!opencv-matrix, ROS's rows/cols/data). `count` 0 accepts any number of them.
Expected<std::vector<double>> numbers(const cv::FileNode& node, const std::string& field,
                                      const std::string& origin, std::size_t count = 0);

// An image size [width, height] of positive integers.
Expected<std::array<int, 2>> imageSize(const cv::FileNode& node, const std::string& field,
                                       const std::string& origin);

// Positive, finite focal lengths and a finite principal point.
Status checkIntrinsics(const Intrinsics& k, const std::string& field, const std::string& origin);
// A proper rotation and a translation of plausible size in meters.
Status checkTransform(const RigidTransform& transform, const std::string& rotationField,
                      const std::string& translationField, const std::string& origin);

Error fieldError(const std::string& origin, const std::string& field, const std::string& problem);

} // namespace dc::frame::fields
