#pragma once

#include "base/expected.h"
#include "devices/ros/ros_link.h"

#include <chrono>
#include <memory>
#include <string>
#include <vector>

// ROS 2's topics, heard over DDS with Eclipse Cyclone DDS. ROS 2 names a topic /a/b rt/a/b on the wire and
// its types sensor_msgs::msg::dds_::Image_; its messages are plain CDR, taken here still serialized and
// decoded by cdr.h, the decoder of ROS 2 bags, so a live message and a recorded one read the same.
namespace dc::devices::ros {

// A ROS 2 topic's DDS topic name: /camera/depth/image_rect_raw -> rt/camera/depth/image_rect_raw.
std::string ddsTopicName(const std::string& rosTopic);

// The largest domain id whose ports RTPS can give (7400 + 250 * id + ... < 65536).
inline constexpr int kMaxRosDomain = 232;
// ROS 2's domain: ROS_DOMAIN_ID, or 0. Fails in one line when ROS_DOMAIN_ID is not 0..232.
Expected<int> rosDomainFromEnvironment();

// The ROS 2 topics whose publishers announced themselves on `domain` within `wait`, sorted, with their
// types in ROS 1's spelling ("sensor_msgs/Image").
Expected<std::vector<TopicInfo>> discoverRos2Topics(int domain, std::chrono::milliseconds wait);

// A live ROS 2 camera's middleware: a DDS participant on `domain`. Images and camera_info are read
// best-effort, which hears both the sensor-data profile's best-effort publishers and reliable ones;
// /tf_static reliably and transient-local, so that transforms published before we came are heard. A depth
// publisher that was heard and leaves (it unmatches: it ended, or its lease ran out) makes the camera
// Disconnected; it is back when a depth publisher matches again.
std::unique_ptr<RosLink> makeDdsLink(int domain);

} // namespace dc::devices::ros
