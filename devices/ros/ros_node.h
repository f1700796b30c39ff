#pragma once

#include "base/expected.h"
#include "devices/ros/ros_link.h"
#include "devices/ros/ros_master.h"
#include "devices/ros/ros_messages.h"

#include <memory>
#include <string>
#include <vector>

// The live half of the roscpp glue, behind plain values (ros_messages.h says why). roscpp keeps one node per
// process: it is started once, against one master, with an anonymous name and without a SIGINT handler
// (the tool owns its signals), and never shut down before the process exits, since roscpp cannot be
// started again after a shutdown. Every roscpp exception is caught here. This header must stay valid C++17.
namespace dc::devices::ros {

// Starts this process's ROS node against `master` (probe it first: roscpp waits for an absent master).
// Fails if the node already talks to another master: roscpp cannot switch.
Status startRosNode(const MasterUri& master);
// The topics that publishers have advertised to the master (after startRosNode).
Expected<std::vector<TopicInfo>> advertisedTopics();

// Subscribes to a depth camera's topics with its own callback queue and spinner thread, so the messages of
// one device never wait behind another's. Destroying it unsubscribes and joins the spinner.
class Subscription {
public:
    static Expected<std::unique_ptr<Subscription>> create(const SubscriptionTopics& topics,
                                                          SubscriptionCallbacks callbacks);
    ~Subscription();
    Subscription(const Subscription&) = delete;
    // Where `frameId` is in the fixed frame at `stampNs`, from /tf and /tf_static (p_fixed = R p + t); the
    // newest transform when /tf has none that recent yet. Thread-safe. Fails, in one line, when the two
    // frames are not connected or no fixed frame was asked for.
    Expected<RosTransform> transform(const std::string& frameId, std::int64_t stampNs) const;
    Subscription& operator=(const Subscription&) = delete;

private:
    struct Impl;
    explicit Subscription(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// A live ROS 1 camera's middleware: the master `masterUri` names (empty: ROS_MASTER_URI), probed with a
// bounded wait before roscpp touches it (roscpp's own calls wait without bound), and TCPROS subscriptions.
// The camera cannot be heard while the master does not answer.
std::unique_ptr<RosLink> makeMasterLink(std::string masterUri);

} // namespace dc::devices::ros
