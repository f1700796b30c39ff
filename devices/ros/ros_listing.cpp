#include "devices/ros/ros_listing.h"

#include "devices/ros/dds_subscription.h"
#include "devices/ros/ros_image.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_node.h"

#include <chrono>
#include <cstdlib>
#include <cstring>

namespace dc::devices::ros {

namespace {

// The image topics (raw or compressed) of a listing, or why there is none.
void keepImageTopics(const Expected<std::vector<TopicInfo>>& topics, std::vector<std::string>& images,
                     std::string& problem) {
    if (!topics) {
        problem = topics.error().message;
        return;
    }
    for (const TopicInfo& t : *topics)
        if (t.type == kRosImageType || t.type == kRosCompressedImageType)
            images.push_back(t.name);
}

} // namespace

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
    keepImageTopics(topics, listing.imageTopics, listing.problem);
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
    keepImageTopics(topics, listing.imageTopics, listing.problem);
    return listing;
}

} // namespace dc::devices::ros
