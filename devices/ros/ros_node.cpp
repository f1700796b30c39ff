// Compiled as C++17: includes Debian's ROS 1 headers (ros_messages.h says why).
#include "devices/ros/ros_node.h"

#include "devices/ros/live_tf.h"
#include "devices/ros/ros_conversions.h"

#include <ros/callback_queue.h>
#include <ros/master.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <mutex>

namespace dc::devices::ros {

namespace {

// How long roscpp keeps retrying a master call (registering a subscriber) before giving up; without a bound
// it retries forever when the master vanished between our probe and the call.
constexpr double kMasterRetrySeconds = 2.0;
constexpr std::uint32_t kImageQueueSize = 2; // latest wins: a slow consumer sees new images, not old ones
constexpr std::uint32_t kTfQueueSize = 100;  // /tf carries many small messages from many publishers

std::mutex& nodeMutex() {
    static std::mutex mutex;
    return mutex;
}

std::string withoutTrailingSlash(std::string uri) {
    if (!uri.empty() && uri.back() == '/')
        uri.pop_back();
    return uri;
}

} // namespace

Status startRosNode(const MasterUri& master) {
    const std::lock_guard lock(nodeMutex());
    try {
        if (::ros::isInitialized()) {
            const std::string current = withoutTrailingSlash(::ros::master::getURI());
            if (current != withoutTrailingSlash(master.uri))
                return Error{"this process already talks to ROS master " + current +
                             "; restart depthcloud to use " + master.uri};
            return {};
        }
        const ::ros::M_string remappings{{"__master", master.uri}};
        ::ros::init(remappings, "depthcloud",
                    ::ros::init_options::NoSigintHandler | ::ros::init_options::AnonymousName |
                        ::ros::init_options::NoRosout);
        ::ros::master::setRetryTimeout(::ros::WallDuration(kMasterRetrySeconds));
        // Started explicitly, so that dropping the last NodeHandle does not shut the node down.
        ::ros::start();
    } catch (const std::exception& e) {
        return Error{std::string("cannot start the ROS node: ") + e.what()};
    }
    return {};
}

Expected<std::vector<TopicInfo>> advertisedTopics() {
    ::ros::master::V_TopicInfo found;
    try {
        if (!::ros::master::getTopics(found))
            return Error{"the ROS master at " + ::ros::master::getURI() + " did not list its topics"};
    } catch (const std::exception& e) {
        return Error{std::string("cannot list ROS topics: ") + e.what()};
    }
    std::vector<TopicInfo> topics;
    for (const ::ros::master::TopicInfo& t : found)
        topics.push_back({t.name, t.datatype});
    std::sort(topics.begin(), topics.end(),
              [](const TopicInfo& a, const TopicInfo& b) { return a.name < b.name; });
    return topics;
}

struct Subscription::Impl {
    SubscriptionCallbacks callbacks;
    ::ros::CallbackQueue queue;
    std::unique_ptr<::ros::NodeHandle> node;
    std::unique_ptr<::ros::AsyncSpinner> spinner;
    std::vector<::ros::Subscriber> subscribers;
    SubscriptionTopics topics;
    std::unique_ptr<LiveTf> tf;

    // An exception thrown into roscpp's spinner would end its thread: a message we cannot copy is dropped.
    template <class Deliver> static void guarded(Deliver&& deliver) {
        try {
            deliver();
        } catch (const std::exception& e) {
            ROS_WARN_THROTTLE(5.0, "depthcloud dropped a message: %s", e.what());
        }
    }
    void onDepth(const sensor_msgs::ImageConstPtr& m) {
        guarded([&] { callbacks.depth(toImage(*m)); });
    }
    void onColor(const sensor_msgs::ImageConstPtr& m) {
        guarded([&] { callbacks.color(toImage(*m)); });
    }
    // Decoded here, on the spinner thread, so that the device sees plain images whatever the transport.
    void deliverCompressed(const sensor_msgs::CompressedImage& m, const std::string& topic,
                           const std::function<void(RosImage)>& deliver) {
        guarded([&] {
            auto image = decompressed(m);
            if (image)
                deliver(std::move(*image));
            else
                callbacks.problem(topic + ": " + image.error().message);
        });
    }
    void onDepthCompressed(const sensor_msgs::CompressedImageConstPtr& m) {
        deliverCompressed(*m, topics.depth, callbacks.depth);
    }
    void onColorCompressed(const sensor_msgs::CompressedImageConstPtr& m) {
        deliverCompressed(*m, topics.color, callbacks.color);
    }
    void onInfo(const sensor_msgs::CameraInfoConstPtr& m) {
        guarded([&] { callbacks.info(toCameraInfo(*m)); });
    }
    void onTf(const tf2_msgs::TFMessageConstPtr& m, bool isStatic) {
        for (const geometry_msgs::TransformStamped& t : m->transforms)
            guarded([&] { tf->add(toTransformStamped(t), isStatic); });
    }
    void onTfDynamic(const tf2_msgs::TFMessageConstPtr& m) { onTf(m, false); }
    void onTfStatic(const tf2_msgs::TFMessageConstPtr& m) { onTf(m, true); }

    void subscribe(const SubscriptionTopics& wanted) {
        topics = wanted;
        node = std::make_unique<::ros::NodeHandle>();
        node->setCallbackQueue(&queue);
        const auto hints = ::ros::TransportHints().tcpNoDelay();
        subscribers.push_back(
            topics.depthCompressed
                ? node->subscribe(topics.depth, kImageQueueSize, &Impl::onDepthCompressed, this, hints)
                : node->subscribe(topics.depth, kImageQueueSize, &Impl::onDepth, this, hints));
        if (!topics.color.empty())
            subscribers.push_back(
                topics.colorCompressed
                    ? node->subscribe(topics.color, kImageQueueSize, &Impl::onColorCompressed, this, hints)
                    : node->subscribe(topics.color, kImageQueueSize, &Impl::onColor, this, hints));
        subscribers.push_back(node->subscribe(topics.info, 1, &Impl::onInfo, this, hints));
        tf = std::make_unique<LiveTf>(topics.fixedFrame);
        if (!topics.fixedFrame.empty()) {
            subscribers.push_back(node->subscribe("/tf", kTfQueueSize, &Impl::onTfDynamic, this, hints));
            subscribers.push_back(
                node->subscribe("/tf_static", kTfQueueSize, &Impl::onTfStatic, this, hints));
        }
        spinner = std::make_unique<::ros::AsyncSpinner>(1, &queue);
        spinner->start();
    }

    ~Impl() {
        try {
            if (spinner)
                spinner->stop();
            for (::ros::Subscriber& s : subscribers)
                s.shutdown();
        } catch (const std::exception&) {
            // Unsubscribing from a master that is gone fails; the subscription ends here all the same.
        }
    }
};

Subscription::Subscription(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Subscription::~Subscription() = default;

Expected<RosTransform> Subscription::transform(const std::string& frameId, std::int64_t stampNs) const {
    return impl_->tf->transform(frameId, stampNs);
}

Expected<std::unique_ptr<Subscription>> Subscription::create(const SubscriptionTopics& topics,
                                                             SubscriptionCallbacks callbacks) {
    auto impl = std::make_unique<Impl>();
    impl->callbacks = std::move(callbacks);
    try {
        impl->subscribe(topics);
    } catch (const std::exception& e) {
        return Error{"cannot subscribe to " + topics.depth + ": " + e.what()};
    }
    return std::unique_ptr<Subscription>(new Subscription(std::move(impl)));
}

} // namespace dc::devices::ros
