#include "devices/ros/ros_listing.h"

#include "devices/ros/dds_subscription.h"
#include "devices/ros/ros_image.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_node.h"

#include <chrono>
#include <cstdlib>
#include <cstring>

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

Ros2Listing listRos2ImageTopics() {
    // Long enough for the participants of one host or one switch to announce themselves and their writers.
    constexpr std::chrono::milliseconds kDiscoveryWait{1500};
    Ros2Listing listing;
    const char* domainId = std::getenv("ROS_DOMAIN_ID");
    const char* version = std::getenv("ROS_VERSION");
    listing.configured =
        (domainId != nullptr && *domainId != '\0') || (version != nullptr && std::strcmp(version, "2") == 0);
    if (!listing.configured)
        return listing;
    auto domain = rosDomainFromEnvironment();
    auto topics = domain ? discoverRos2Topics(*domain, kDiscoveryWait)
                         : Expected<std::vector<TopicInfo>>(domain.error());
    listing.domain = domain ? *domain : 0;
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
