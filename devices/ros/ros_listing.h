#pragma once

#include <string>
#include <vector>

namespace dc::devices::ros {

// The image topics of the ROS master that ROS_MASTER_URI names, for `depthcloud devices`. `configured` is
// false when ROS_MASTER_URI is not set (nothing is contacted then); `problem` says why nothing could be
// listed (an unreachable master is found out within a second, never waited for).
struct RosListing {
    bool configured = false;
    std::string masterUri;
    std::vector<std::string> imageTopics; // advertised as sensor_msgs/Image, sorted
    std::string problem;
};

RosListing listRosImageTopics();

// The image topics announced on a ROS 2 domain, for `depthcloud devices`: asked only in a ROS 2 environment
// (ROS_DOMAIN_ID set, or ROS_VERSION=2), and only for as long as discovery takes on a local network.
struct Ros2Listing {
    bool configured = false;
    int domain = 0;
    std::vector<std::string> imageTopics; // sensor_msgs/Image or CompressedImage, sorted
    std::string problem;
};

Ros2Listing listRos2ImageTopics();

} // namespace dc::devices::ros
