#include "devices/ros/ros_listing.h"

#include "devices/ros/ros_image.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_node.h"

#include <cstdlib>

namespace dc::devices::ros {

RosListing listRosImageTopics() {
    RosListing listing;
    const char* env = std::getenv("ROS_MASTER_URI");
    if (env == nullptr || *env == '\0')
        return listing;
    listing.configured = true;
    listing.masterUri = env;
    auto master = parseMasterUri(env);
    Status reached = master ? probeMaster(*master, kMasterProbeTimeout) : Status(master.error());
    if (reached)
        reached = startRosNode(*master);
    auto topics = reached ? advertisedTopics() : Expected<std::vector<TopicInfo>>(reached.error());
    if (!topics) {
        listing.problem = topics.error().message;
        return listing;
    }
    for (const TopicInfo& t : *topics)
        if (t.type == kRosImageType || t.type == kRosCompressedImageType)
            listing.imageTopics.push_back(t.name);
    return listing;
}

} // namespace dc::devices::ros
