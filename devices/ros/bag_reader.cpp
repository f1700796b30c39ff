// Compiled as C++17: includes Debian's ROS 1 headers (ros_messages.h says why).
#include "devices/ros/bag_reader.h"

#include "devices/ros/compressed_image.h"
#include "devices/ros/ros_conversions.h"

#include <geometry_msgs/Transform.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Float32.h>

#include <algorithm>

namespace dc::devices::ros {

namespace {

template <class T> boost::shared_ptr<T> first(const rosbag::Bag& bag, const std::string& topic) {
    try {
        rosbag::View view(bag, rosbag::TopicQuery(topic));
        for (const rosbag::MessageInstance& m : view)
            if (auto message = m.instantiate<T>())
                return message;
    } catch (const std::exception&) {
        // A damaged message is as good as none: the caller falls back to defaults and says so.
    }
    return nullptr;
}

} // namespace

struct BagReader::Impl {
    std::string path;
    rosbag::Bag bag;
    std::vector<Topic> topics;
    std::vector<std::vector<rosbag::MessageInstance>> indexes;
};

BagReader::BagReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BagReader::~BagReader() = default;

Expected<std::unique_ptr<BagReader>> BagReader::open(const std::string& path) {
    auto impl = std::make_unique<Impl>();
    impl->path = path;
    try {
        impl->bag.open(path, rosbag::bagmode::Read);
        rosbag::View all(impl->bag);
        for (const rosbag::ConnectionInfo* c : all.getConnections())
            if (std::none_of(impl->topics.begin(), impl->topics.end(),
                             [&](const Topic& t) { return t.name == c->topic; }))
                impl->topics.push_back({c->topic, c->datatype});
    } catch (const std::exception& e) {
        return Error{path + " is not a readable ROS bag: " + e.what()};
    }
    return std::unique_ptr<BagReader>(new BagReader(std::move(impl)));
}

const std::vector<MessageStore::Topic>& BagReader::topics() const {
    return impl_->topics;
}

Expected<std::size_t> BagReader::indexTopic(const std::string& topic) {
    std::vector<rosbag::MessageInstance> messages;
    try {
        rosbag::View view(impl_->bag, rosbag::TopicQuery(topic));
        for (const rosbag::MessageInstance& m : view)
            messages.push_back(m);
    } catch (const std::exception& e) {
        return Error{impl_->path + ": the index of " + topic + " is unreadable: " + e.what()};
    }
    impl_->indexes.push_back(std::move(messages));
    return impl_->indexes.size() - 1;
}

std::size_t BagReader::messageCount(std::size_t handle) const {
    return impl_->indexes[handle].size();
}

std::int64_t BagReader::recordedNs(std::size_t handle, std::size_t i) const {
    return toNs(impl_->indexes[handle][i].getTime());
}

Expected<RosImage> BagReader::image(std::size_t handle, std::size_t i) const {
    const rosbag::MessageInstance& m = impl_->indexes[handle][i];
    try {
        if (auto message = m.instantiate<sensor_msgs::Image>())
            return toImage(*message);
        if (auto message = m.instantiate<sensor_msgs::CompressedImage>()) {
            auto image = decompressed(*message);
            if (!image)
                return Error{"message " + std::to_string(i) + " on " + m.getTopic() + ": " +
                             image.error().message};
            return image;
        }
        return Error{"message " + std::to_string(i) + " on " + m.getTopic() + " is " + m.getDataType() +
                     ", not sensor_msgs/Image or sensor_msgs/CompressedImage"};
    } catch (const std::exception& e) {
        return Error{"message " + std::to_string(i) + " on " + m.getTopic() + " is unreadable: " + e.what()};
    }
}

std::optional<RosImage> BagReader::firstImage(const std::string& topic) const {
    if (auto m = first<sensor_msgs::Image>(impl_->bag, topic))
        return toImage(*m);
    if (auto m = first<sensor_msgs::CompressedImage>(impl_->bag, topic))
        if (auto image = decompressed(*m))
            return std::move(*image);
    return std::nullopt;
}

std::optional<RosCameraInfo> BagReader::firstCameraInfo(const std::string& topic) const {
    auto m = first<sensor_msgs::CameraInfo>(impl_->bag, topic);
    if (!m)
        return std::nullopt;
    return toCameraInfo(*m);
}

std::optional<float> BagReader::firstFloat32(const std::string& topic) const {
    if (auto m = first<std_msgs::Float32>(impl_->bag, topic))
        return m->data;
    return std::nullopt;
}

std::optional<RosTransform> BagReader::firstTransform(const std::string& topic) const {
    auto m = first<geometry_msgs::Transform>(impl_->bag, topic);
    if (!m)
        return std::nullopt;
    return toTransform(*m);
}

struct BagWriter::Impl {
    std::string path;
    rosbag::Bag bag;
};

BagWriter::BagWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BagWriter::~BagWriter() = default;

Expected<std::unique_ptr<BagWriter>> BagWriter::create(const std::string& path) {
    auto impl = std::make_unique<Impl>();
    impl->path = path;
    try {
        impl->bag.open(path, rosbag::bagmode::Write);
    } catch (const std::exception& e) {
        return Error{"cannot create ROS bag " + path + ": " + e.what()};
    }
    return std::unique_ptr<BagWriter>(new BagWriter(std::move(impl)));
}

Status BagWriter::write(const std::string& topic, const RosImage& image) {
    sensor_msgs::Image m;
    m.header.stamp.fromNSec(static_cast<std::uint64_t>(image.stampNs));
    m.header.frame_id = image.frameId;
    m.encoding = image.encoding;
    m.width = image.width;
    m.height = image.height;
    m.step = image.step;
    m.is_bigendian = image.bigEndian ? 1 : 0;
    m.data = image.data;
    try {
        impl_->bag.write(topic, m.header.stamp, m);
    } catch (const std::exception& e) {
        return Error{"cannot write " + topic + " to " + impl_->path + ": " + e.what()};
    }
    return {};
}

Status BagWriter::write(const std::string& topic, std::int64_t stampNs, const RosCameraInfo& info) {
    sensor_msgs::CameraInfo m;
    m.header.stamp.fromNSec(static_cast<std::uint64_t>(stampNs));
    m.width = info.width;
    m.height = info.height;
    std::copy(info.k.begin(), info.k.end(), m.K.begin());
    m.distortion_model = info.distortionModel;
    m.D = info.d;
    try {
        impl_->bag.write(topic, m.header.stamp, m);
    } catch (const std::exception& e) {
        return Error{"cannot write " + topic + " to " + impl_->path + ": " + e.what()};
    }
    return {};
}

Status BagWriter::close() {
    try {
        impl_->bag.close();
    } catch (const std::exception& e) {
        return Error{"cannot finish ROS bag " + impl_->path + ": " + e.what()};
    }
    return {};
}

} // namespace dc::devices::ros
