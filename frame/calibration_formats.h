#pragma once

#include "base/expected.h"
#include "frame/calibration.h"

#include <string>
#include <yaml-cpp/yaml.h>

// The two-sensor formats, each read from a parsed document's root and written as text (calibration.h).
namespace dc::frame::formats {

bool isOpenCvStereo(const YAML::Node& root);
Expected<Calibration> readOpenCvStereo(const YAML::Node& root, const std::string& origin, bool json);
Expected<std::string> writeOpenCvStereo(const RigCalibration& rig, bool json);

bool isKalibr(const YAML::Node& root);
Expected<Calibration> readKalibr(const YAML::Node& root, const std::string& origin);
Expected<std::string> writeKalibr(const RigCalibration& rig);

} // namespace dc::frame::formats
