#include "devices/ros/ros_image.h"
#include "devices/ros/ros_node.h"

#include <algorithm>

namespace dc::devices::ros {

namespace {

constexpr const char* kCameraInfoType = "sensor_msgs/CameraInfo";

class MasterLink final : public RosLink {
public:
    explicit MasterLink(std::string masterUri) : masterUri_(std::move(masterUri)) {}

    std::string where() const override { return "ROS master " + master_.uri; }

    Status open(SubscriptionTopics& topics) override {
        if (Status s = connect(); !s)
            return s;
        return checkTopicTypes(topics);
    }

    Status subscribe(const SubscriptionTopics& topics, SubscriptionCallbacks callbacks) override {
        subscription_.reset();
        auto subscription = Subscription::create(topics, std::move(callbacks));
        if (!subscription)
            return subscription.error();
        subscription_ = std::move(*subscription);
        return {};
    }

    void unsubscribe() override { subscription_.reset(); }

    // Publishers may keep sending over their own connections, but nothing new can be found without the
    // master: stop listening until it is back.
    Status alive() override {
        Status alive = probeMaster(master_, kMasterProbeTimeout);
        if (!alive)
            subscription_.reset();
        return alive;
    }

    Status reconnect(const SubscriptionTopics& topics, SubscriptionCallbacks callbacks) override {
        if (Status s = connect(); !s)
            return s;
        return subscribe(topics, std::move(callbacks));
    }

    Expected<RosTransform> transform(const std::string& frameId, std::int64_t stampNs) const override {
        if (!subscription_)
            return Error{"not subscribed to /tf"};
        return subscription_->transform(frameId, stampNs);
    }

private:
    Status connect();
    Status checkTopicTypes(SubscriptionTopics& topics) const;

    std::string masterUri_;
    MasterUri master_;
    std::unique_ptr<Subscription> subscription_;
};

Status MasterLink::connect() {
    auto master = resolveMasterUri(masterUri_);
    if (!master)
        return master.error();
    master_ = *master;
    if (Status s = probeMaster(master_, kMasterProbeTimeout); !s)
        return s;
    return startRosNode(master_);
}

// A topic advertised with another type would subscribe without ever delivering (roscpp refuses the
// connection): say so now. An image topic may be raw or compressed (image_transport's compressed and
// compressedDepth); one nobody advertises yet is taken as its name says, and the watchdog shows it as
// Stalled until it comes.
Status MasterLink::checkTopicTypes(SubscriptionTopics& wanted) const {
    auto topics = advertisedTopics();
    if (!topics)
        return topics.error();
    const auto advertised = [&](const std::string& name) -> const TopicInfo* {
        const auto it =
            std::find_if(topics->begin(), topics->end(), [&](const TopicInfo& t) { return t.name == name; });
        return it == topics->end() ? nullptr : &*it;
    };
    const std::pair<const std::string*, bool*> images[] = {{&wanted.depth, &wanted.depthCompressed},
                                                           {&wanted.color, &wanted.colorCompressed}};
    for (const auto& [name, compressed] : images) {
        *compressed = namesCompressedTransport(*name);
        if (const TopicInfo* t = advertised(*name)) {
            if (t->type != kRosImageType && t->type != kRosCompressedImageType)
                return Error{"ROS topic " + t->name + " carries " + t->type + ", not " + kRosImageType +
                             " or " + kRosCompressedImageType};
            *compressed = t->type == kRosCompressedImageType;
        }
    }
    if (const TopicInfo* t = advertised(wanted.info); t && t->type != kCameraInfoType)
        return Error{"ROS topic " + t->name + " carries " + t->type + ", not " + kCameraInfoType};
    return {};
}

} // namespace

std::unique_ptr<RosLink> makeMasterLink(std::string masterUri) {
    return std::make_unique<MasterLink>(std::move(masterUri));
}

} // namespace dc::devices::ros
