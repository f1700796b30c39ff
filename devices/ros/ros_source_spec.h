#pragma once

#include "base/expected.h"
#include "devices/device.h"

#include <chrono>
#include <memory>
#include <string>

namespace dc::devices::ros {

// --source ros:DEPTH_TOPIC[:OPTION...]
//   color=TOPIC|none   the camera image (default: found beside the depth topic, see deriveTopics)
//   info=TOPIC         the depth camera's sensor_msgs/CameraInfo (default: beside the depth topic)
//   master=URI         http://HOST:PORT (default: ROS_MASTER_URI)
//   tolerance=MS       largest depth/colour stamp difference that still pairs (default 20)
//   watchdog=MS        no depth image for this long shows "Stalled" (default 2000)
//   frame=FIXED_FRAME  each frame's pose: where the depth image's frame_id (an optical frame, so OpenCV's
//                      camera axes) is in FIXED_FRAME, from /tf and /tf_static
inline constexpr const char* kRosSourceSpecHelp =
    "ros:DEPTH_TOPIC[:color=TOPIC|none][:info=TOPIC][:master=http://HOST:PORT][:tolerance=MS][:watchdog=MS]"
    "[:frame=FIXED_FRAME]";
// --source ros2:DEPTH_TOPIC[:OPTION...]: the same options, but domain=N (0..232; default ROS_DOMAIN_ID, or 0)
// for master=. The DDS participant reads Cyclone DDS's configuration from CYCLONEDDS_URI as ROS 2 does.
inline constexpr const char* kRos2SourceSpecHelp =
    "ros2:DEPTH_TOPIC[:color=TOPIC|none][:info=TOPIC][:domain=N][:tolerance=MS][:watchdog=MS]"
    "[:frame=FIXED_FRAME]";

struct RosSourceConfig {
    std::string depthTopic;
    std::string colorTopic; // empty: depth only
    std::string infoTopic;
    std::string masterUri; // empty: ROS_MASTER_URI
    std::chrono::milliseconds pairTolerance{20};
    std::chrono::milliseconds watchdog{2000};
    std::string fixedFrame; // empty: no pose
    bool ros2 = false;      // ROS 2 over DDS, on `domain`
    int domain = -1;        // -1: ROS_DOMAIN_ID, or 0
};

// The topics beside a depth topic, named the way ROS camera drivers (realsense2_camera, openni2,
// astra) name them: camera_info in the depth topic's own namespace, and, when that namespace's last part
// names depth (depth, aligned_depth_to_color, depth_registered), the colour image as color/image_raw
// beside it. /camera/depth/image_rect_raw -> /camera/color/image_raw and /camera/depth/camera_info.
// Without a depth namespace there is no colour to guess: depth only, unless color= names one.
struct DerivedTopics {
    std::string color;
    std::string info;
};
DerivedTopics deriveTopics(const std::string& depthTopic);

// Parse the part after "ros:" or "ros2:" without contacting ROS. Errors name the offending option.
Expected<RosSourceConfig> parseRosSourceSpec(const std::string& spec);
Expected<RosSourceConfig> parseRos2SourceSpec(const std::string& spec);
Expected<std::unique_ptr<Device>> openRosSourceSpec(const std::string& spec);
Expected<std::unique_ptr<Device>> openRos2SourceSpec(const std::string& spec);

} // namespace dc::devices::ros
