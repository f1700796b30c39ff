#pragma once

#include "base/expected.h"
#include "frame/calibration.h"

#include <opencv2/core.hpp>
#include <string>

// The two-sensor formats, each read from an opened FileStorage and written as text (calibration.h).
namespace dc::frame::formats {

bool isOpenCvStereo(const cv::FileStorage& fs);
Expected<Calibration> readOpenCvStereo(const cv::FileStorage& fs, const std::string& origin, bool json);
Expected<std::string> writeOpenCvStereo(const RigCalibration& rig, bool json);

bool isKalibr(const cv::FileStorage& fs);
Expected<Calibration> readKalibr(const cv::FileStorage& fs, const std::string& origin);
Expected<std::string> writeKalibr(const RigCalibration& rig);

} // namespace dc::frame::formats
