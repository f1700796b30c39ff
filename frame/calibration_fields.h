#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"

#include <array>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>
#include <yaml-cpp/yaml.h>

// What the calibration readers share: the document, fields read as numbers, and checks that name the field
// at fault.
namespace dc::frame::fields {

// A calibration file's root, parsed by yaml-cpp (JSON is read as the YAML it is). A syntax error names the
// file, line and column.
Expected<YAML::Node> parseDocument(const std::string& text, const std::string& origin);

// The field `name` of a map; undefined when `parent` is not a map, lacks it or gives it no value. yaml-cpp's
// own lookup returns a node that throws when asked its type, so the readers never use it directly.
YAML::Node child(const YAML::Node& parent, const std::string& name);
bool has(const YAML::Node& parent, const std::string& name);

// The first of `names` present in `parent`, with the name it was found under (the first name if none).
struct Named {
    YAML::Node node;
    std::string name;
};
Named firstOf(const YAML::Node& parent, std::initializer_list<std::string> names);

// A scalar's text; empty for a map, a sequence or nothing.
std::string text(const YAML::Node& node);
// A plain (unquoted) scalar read as a number; YAML's .inf and any spelling of nan too, for the checks to
// refuse.
std::optional<double> number(const YAML::Node& node);

// The numbers of a field: a number, a sequence (nested sequences flattened, row by row) or a matrix map
// with `data` (OpenCV's !!opencv-matrix, ROS's rows/cols/data). `count` 0 accepts any number of them.
Expected<std::vector<double>> numbers(const YAML::Node& node, const std::string& field,
                                      const std::string& origin, std::size_t count = 0);

// An image size [width, height] of positive integers.
Expected<std::array<int, 2>> imageSize(const YAML::Node& node, const std::string& field,
                                       const std::string& origin);

// A 4x4 row-major homogeneous matrix (any form `numbers` reads) whose last row is [0, 0, 0, 1], as a
// transform; whether its rotation is one is the caller's check.
Expected<RigidTransform> homogeneousMatrix(const YAML::Node& node, const std::string& field,
                                           const std::string& origin);

// Positive, finite focal lengths and a finite principal point.
Status checkIntrinsics(const Intrinsics& k, const std::string& field, const std::string& origin);
// A proper rotation and a translation of plausible size in meters.
Status checkTransform(const RigidTransform& transform, const std::string& rotationField,
                      const std::string& translationField, const std::string& origin);

Error fieldError(const std::string& origin, const std::string& field, const std::string& problem);

} // namespace dc::frame::fields
