#pragma once

// ROS 1 messages -> the plain values of ros_messages.h. Includes Debian's generated message headers, so
// only the C++17 glue files (bag_reader.cpp, ros_node.cpp) may include this header.

#include "devices/ros/compressed_image.h"
#include "devices/ros/ros_messages.h"

#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <algorithm>

namespace dc::devices::ros {

inline std::int64_t toNs(const ::ros::Time& t) {
    return static_cast<std::int64_t>(t.sec) * 1'000'000'000 + t.nsec;
}

inline RosImage toImage(const sensor_msgs::Image& m) {
    RosImage image;
    image.stampNs = toNs(m.header.stamp);
    image.frameId = m.header.frame_id;
    image.encoding = m.encoding;
    image.width = m.width;
    image.height = m.height;
    image.step = m.step;
    image.bigEndian = m.is_bigendian != 0;
    image.data = m.data;
    return image;
}

// image_transport's compressed and compressedDepth topics, as the plain image the raw topic carries.
inline Expected<RosImage> decompressed(const sensor_msgs::CompressedImage& m) {
    auto image = decompressImage(m.format, m.data.data(), m.data.size());
    if (!image)
        return image.error();
    image->stampNs = toNs(m.header.stamp);
    image->frameId = m.header.frame_id;
    return image;
}

inline RosCameraInfo toCameraInfo(const sensor_msgs::CameraInfo& m) {
    RosCameraInfo info;
    info.width = m.width;
    info.height = m.height;
    std::copy(m.K.begin(), m.K.end(), info.k.begin());
    info.distortionModel = m.distortion_model;
    info.d = m.D;
    return info;
}

inline RosTransform toTransform(const geometry_msgs::Transform& m) {
    return RosTransform{{m.translation.x, m.translation.y, m.translation.z},
                        {m.rotation.x, m.rotation.y, m.rotation.z, m.rotation.w}};
}

inline RosTransformStamped toTransformStamped(const geometry_msgs::TransformStamped& m) {
    return RosTransformStamped{toNs(m.header.stamp), m.header.frame_id, m.child_frame_id,
                               toTransform(m.transform)};
}

} // namespace dc::devices::ros
