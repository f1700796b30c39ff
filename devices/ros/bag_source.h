#pragma once

#include "base/expected.h"
#include "devices/replay/replay_source.h"
#include "devices/ros/message_store.h"
#include "devices/ros/ros_image.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices::ros {

struct BagOptions {
    // Image topics to replay; a depth topic alone replays without colour. Empty: both found by their
    // encodings (RealSense's Depth_0 and Color_0 first, then topics named depth and color).
    std::string depthTopic{};
    std::string colorTopic{};
    // A colour image belongs to the depth image nearest in time within this gap (TUM's associate.py default).
    double maxPairGapSeconds = 0.02;
};

// Depth -> colour extrinsics: p_color = rotation * p_depth + translationMeters, rotation row-major.
struct BagExtrinsics {
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::array<double, 3> translationMeters{0, 0, 0};
};

// What a bag records about its two sensors, kept for two-sensor registration: each stream's camera_info
// and, in a RealSense bag, where the colour camera sits relative to the depth camera.
struct BagRig {
    std::optional<CameraInfoRecord> depth;
    std::optional<CameraInfoRecord> color;
    std::optional<BagExtrinsics> depthToColor;
};

// A ROS 1 bag (format 2.0) as a replay source: a RealSense recording (/device_0/sensor_N/<Stream>_0/...,
// depth units from the sensor's "Depth Units" option, extrinsics from the streams' tf topics) or any bag
// with sensor_msgs/Image topics and camera_info beside them. Frames are the depth images in recorded order,
// each with the colour image nearest in time; timestamps are the images' header stamps.
Expected<std::unique_ptr<replay::ReplaySource>> openBagSource(const std::string& path,
                                                              const BagOptions& options = {});

// Any recording of ROS topics replayed the same way: `path` names it in descriptions and errors;
// `warnings` are what the caller noticed in opening it, listed before the replay's own.
Expected<std::unique_ptr<replay::ReplaySource>> openMessageSource(std::unique_ptr<MessageStore> store,
                                                                  const std::string& path,
                                                                  const BagOptions& options = {},
                                                                  std::vector<std::string> warnings = {});

// The recorded calibration of a source that openBagSource opened; nullptr for any other source.
const BagRig* bagRig(const replay::ReplaySource& source);

} // namespace dc::devices::ros
