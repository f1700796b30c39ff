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

} // namespace dc::devices::ros
