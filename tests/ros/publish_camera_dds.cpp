// A ROS 2 camera on another DDS than depthcloud's: eProsima Fast DDS publishes what realsense2_camera's ROS 2
// wrapper does, with ROS 2's wire names (rt/camera/camera/depth/image_rect_raw,
// sensor_msgs::msg::dds_::Image_): 16UC1 depth, rgb8 colour, the depth camera_info, and /tf plus /tf_static
// when --tf-root is given. The messages are serialized by Fast CDR, field by field as ROS 2 defines them, so
// depthcloud's decoder is checked against an encoder it does not share. Pixels, stamps and lens follow
// camera_pattern.h (or, with --stamps realtime, the stamps are the wall clock at publishing, for latency).
// Runs until killed (or
// --frames are sent); with --loopback its participant talks over 127.0.0.1 only, discovering by unicast.
#include "tests/ros/camera_pattern.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace dds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using eprosima::fastcdr::Cdr;
using namespace dc::test::camera;

struct Options {
    int domain = 0;
    std::string ns = "/camera/camera";
    int width = 848, height = 480, colorWidth = 848, colorHeight = 480;
    double colorSkewMs = 0.0;
    std::string tfRoot;
    bool bestEffort = false; // ROS 2's sensor-data profile; else its default, reliable
    bool loopback = false;
    long frames = 0; // 0: until killed
    int leaseMs = 2000;
    // Stamped with the wall clock when published (for latency), not the pattern's.
    bool realtimeStamps = false;
    bool depthIsString = false; // the depth topic carries std_msgs/String: a topic of another type
};

// A message already serialized, handed to Fast DDS as it is.
struct Serialized {
    std::vector<char> bytes;
};

class SerializedType final : public dds::TopicDataType {
public:
    SerializedType(const std::string& name, std::uint32_t largest) {
        setName(name.c_str());
        m_typeSize = largest;
        m_isGetKeyDefined = false;
    }
    bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
        const auto& bytes = static_cast<Serialized*>(data)->bytes;
        if (bytes.size() > payload->max_size)
            return false;
        std::memcpy(payload->data, bytes.data(), bytes.size());
        payload->length = static_cast<std::uint32_t>(bytes.size());
        payload->encapsulation = CDR_LE;
        return true;
    }
    bool deserialize(rtps::SerializedPayload_t*, void*) override { return false; }
    std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
        return [data] { return static_cast<std::uint32_t>(static_cast<Serialized*>(data)->bytes.size()); };
    }
    void* createData() override { return new Serialized; }
    void deleteData(void* data) override { delete static_cast<Serialized*>(data); }
    bool getKey(void*, rtps::InstanceHandle_t*, bool) override { return false; }
};

// Serializes with Fast CDR into a buffer of `capacity`, little endian, encapsulation header first.
template <class Write> Serialized serialized(std::size_t capacity, Write&& write) {
    Serialized out;
    out.bytes.resize(capacity);
    eprosima::fastcdr::FastBuffer buffer(out.bytes.data(), out.bytes.size());
    Cdr cdr(buffer, Cdr::LITTLE_ENDIANNESS, Cdr::DDS_CDR);
    cdr.serialize_encapsulation();
    write(cdr);
    out.bytes.resize(cdr.getSerializedDataLength());
    return out;
}

void header(Cdr& cdr, std::int64_t stampNs, const std::string& frameId) {
    cdr << static_cast<std::int32_t>(stampNs / 1'000'000'000)
        << static_cast<std::uint32_t>(stampNs % 1'000'000'000) << frameId;
}

Serialized image(std::int64_t stampNs, const std::string& encoding, int width, int height, int bytesPerPixel,
                 const std::vector<std::uint8_t>& data) {
    return serialized(data.size() + 256, [&](Cdr& cdr) {
        header(cdr, stampNs, "camera_depth_optical_frame");
        cdr << static_cast<std::uint32_t>(height) << static_cast<std::uint32_t>(width) << encoding
            << static_cast<std::uint8_t>(0) << static_cast<std::uint32_t>(width * bytesPerPixel) << data;
    });
}

std::vector<std::uint8_t> depthBytes(const Options& o, std::int64_t i) {
    std::vector<std::uint8_t> bytes(2 * static_cast<std::size_t>(o.width) * o.height);
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            const std::uint16_t units = depthUnits(x, y, i);
            std::memcpy(&bytes[2 * (static_cast<std::size_t>(y) * o.width + x)], &units, 2); // little endian
        }
    return bytes;
}

std::vector<std::uint8_t> colorBytes(const Options& o, std::int64_t i) {
    std::vector<std::uint8_t> bytes(3 * static_cast<std::size_t>(o.colorWidth) * o.colorHeight);
    for (int y = 0; y < o.colorHeight; ++y)
        for (int x = 0; x < o.colorWidth; ++x) {
            const auto rgb = colorRgb(x, y, i);
            std::memcpy(&bytes[3 * (static_cast<std::size_t>(y) * o.colorWidth + x)], rgb.data(), 3);
        }
    return bytes;
}

Serialized cameraInfo(const Options& o, std::int64_t stampNs) {
    const double sx = o.width / 64.0, sy = o.height / 48.0;
    const std::array<double, 9> k{kFx * sx, 0, kCx * sx, 0, kFy * sy, kCy * sy, 0, 0, 1};
    const std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::array<double, 12> p{k[0], 0, k[2], 0, 0, k[4], k[5], 0, 0, 0, 1, 0};
    return serialized(1024, [&](Cdr& cdr) {
        header(cdr, stampNs, "camera_depth_optical_frame");
        cdr << static_cast<std::uint32_t>(o.height) << static_cast<std::uint32_t>(o.width)
            << std::string("plumb_bob") << std::vector<double>(5, 0.0) << k << r << p << std::uint32_t{0}
            << std::uint32_t{0};
        cdr << std::uint32_t{0} << std::uint32_t{0} << std::uint32_t{0} << std::uint32_t{0} << false; // roi
    });
}

struct Transform {
    std::string parent, child;
    std::array<double, 3> xyz;
    std::array<double, 4> xyzw;
};

Serialized tfMessage(std::int64_t stampNs, const Transform& t) {
    return serialized(512, [&](Cdr& cdr) {
        cdr << std::uint32_t{1};
        header(cdr, stampNs, t.parent);
        cdr << t.child << t.xyz << t.xyzw;
    });
}

// camera_link -> the depth image's optical frame: turned 90 degrees about z, sliding 1 cm a frame (as
// publish_camera.py's); root -> camera_link is 1 m up, on /tf_static.
Transform cameraTf(std::int64_t i) {
    const double quarter = std::sqrt(0.5);
    return {"camera_link",
            "camera_depth_optical_frame",
            {0.01 * static_cast<double>(i % 50), 0.5, -0.25},
            {0, 0, quarter, quarter}};
}

class Camera {
public:
    explicit Camera(const Options& o) : o_(o) {}
    ~Camera() {
        if (participant_) {
            participant_->delete_contained_entities();
            dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
        }
    }
    bool start();
    void publish(std::int64_t i);

private:
    dds::DomainParticipantQos participantQos() const;
    dds::DataWriter* writer(const std::string& rosTopic, const std::string& type, std::uint32_t largest,
                            bool transientLocal);

    Options o_;
    dds::DomainParticipant* participant_ = nullptr;
    dds::Publisher* publisher_ = nullptr;
    std::map<std::string, dds::DataWriter*> writers_;
};

dds::DomainParticipantQos Camera::participantQos() const {
    dds::DomainParticipantQos qos;
    qos.name("depthcloud_test_camera");
    auto& discovery = qos.wire_protocol().builtin.discovery_config;
    discovery.leaseDuration = eprosima::fastrtps::Duration_t(o_.leaseMs / 1000.0);
    discovery.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(o_.leaseMs / 4000.0);
    if (o_.loopback) {
        qos.transport().use_builtin_transports = false;
        auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
        udp->interfaceWhiteList.push_back("127.0.0.1");
        qos.transport().user_transports.push_back(udp);
        rtps::Locator_t peer;
        eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, 127, 0, 0, 1);
        qos.wire_protocol().builtin.initialPeersList.push_back(peer);
    }
    return qos;
}

dds::DataWriter* Camera::writer(const std::string& rosTopic, const std::string& type, std::uint32_t largest,
                                bool transientLocal) {
    dds::TypeSupport support(new SerializedType(type, largest));
    support.register_type(participant_);
    dds::Topic* topic = participant_->create_topic("rt" + rosTopic, type, dds::TOPIC_QOS_DEFAULT);
    if (topic == nullptr)
        return nullptr;
    dds::DataWriterQos qos = dds::DATAWRITER_QOS_DEFAULT;
    qos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = transientLocal ? 1 : 5;
    qos.reliability().kind =
        o_.bestEffort && !transientLocal ? dds::BEST_EFFORT_RELIABILITY_QOS : dds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind =
        transientLocal ? dds::TRANSIENT_LOCAL_DURABILITY_QOS : dds::VOLATILE_DURABILITY_QOS;
    qos.publish_mode().kind = dds::ASYNCHRONOUS_PUBLISH_MODE; // images are larger than a datagram
    qos.endpoint().history_memory_policy = rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
    return publisher_->create_datawriter(topic, qos);
}

bool Camera::start() {
    participant_ = dds::DomainParticipantFactory::get_instance()->create_participant(
        static_cast<dds::DomainId_t>(o_.domain), participantQos());
    if (participant_ == nullptr)
        return false;
    publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    const std::uint32_t depthSize = 2u * o_.width * o_.height + 256;
    const std::uint32_t colorSize = 3u * o_.colorWidth * o_.colorHeight + 256;
    writers_["depth"] =
        o_.depthIsString
            ? writer(o_.ns + "/depth/image_rect_raw", "std_msgs::msg::dds_::String_", 256, false)
            : writer(o_.ns + "/depth/image_rect_raw", "sensor_msgs::msg::dds_::Image_", depthSize, false);
    writers_["color"] =
        writer(o_.ns + "/color/image_raw", "sensor_msgs::msg::dds_::Image_", colorSize, false);
    writers_["info"] =
        writer(o_.ns + "/depth/camera_info", "sensor_msgs::msg::dds_::CameraInfo_", 1024, false);
    if (!o_.tfRoot.empty()) {
        writers_["tf"] = writer("/tf", "tf2_msgs::msg::dds_::TFMessage_", 512, false);
        writers_["tf_static"] = writer("/tf_static", "tf2_msgs::msg::dds_::TFMessage_", 512, true);
    }
    for (const auto& [name, w] : writers_)
        if (w == nullptr)
            return false;
    if (!o_.tfRoot.empty()) {
        Serialized up = tfMessage(0, {o_.tfRoot, "camera_link", {0, 0, 1}, {0, 0, 0, 1}});
        writers_["tf_static"]->write(&up);
    }
    return true;
}

std::int64_t wallClockNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

void Camera::publish(std::int64_t i) {
    std::vector<std::uint8_t> depthPixels = depthBytes(o_, i), colorPixels = colorBytes(o_, i);
    const std::int64_t stampNs = o_.realtimeStamps ? wallClockNs() : kStartNs + i * kPeriodNs;
    const auto colorStamp = stampNs + static_cast<std::int64_t>(std::llround(o_.colorSkewMs * 1e6));
    Serialized color = image(colorStamp, "rgb8", o_.colorWidth, o_.colorHeight, 3, colorPixels);
    Serialized depth = o_.depthIsString
                           ? serialized(256, [](Cdr& cdr) { cdr << std::string("not an image"); })
                           : image(stampNs, "16UC1", o_.width, o_.height, 2, depthPixels);
    Serialized info = cameraInfo(o_, stampNs);
    if (!o_.tfRoot.empty()) { // before the images: a receiver finds the pose when the image comes
        Serialized tf = tfMessage(stampNs, cameraTf(i));
        writers_["tf"]->write(&tf);
    }
    writers_["info"]->write(&info);
    writers_["color"]->write(&color);
    writers_["depth"]->write(&depth);
}

bool parse(int argc, char** argv, Options& o) {
    for (int a = 1; a + 1 < argc; a += 2) {
        const std::string key = argv[a], value = argv[a + 1];
        if (key == "--domain")
            o.domain = std::stoi(value);
        else if (key == "--ns")
            o.ns = value;
        else if (key == "--size")
            std::sscanf(value.c_str(), "%dx%d", &o.width, &o.height);
        else if (key == "--color-size")
            std::sscanf(value.c_str(), "%dx%d", &o.colorWidth, &o.colorHeight);
        else if (key == "--color-skew-ms")
            o.colorSkewMs = std::stod(value);
        else if (key == "--tf-root")
            o.tfRoot = value;
        else if (key == "--qos")
            o.bestEffort = value == "sensor-data";
        else if (key == "--loopback")
            o.loopback = value == "1";
        else if (key == "--frames")
            o.frames = std::stol(value);
        else if (key == "--lease-ms")
            o.leaseMs = std::stoi(value);
        else if (key == "--depth-type")
            o.depthIsString = value == "string";
        else if (key == "--stamps")
            o.realtimeStamps = value == "realtime";
        else
            return false;
    }
    return argc % 2 == 1;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, o)) {
        std::fprintf(
            stderr, "usage: publish_camera_dds [--domain N] [--ns NS] [--size WxH] [--color-size WxH] "
                    "[--color-skew-ms MS] [--tf-root FRAME] [--qos sensor-data|default] [--loopback 0|1] "
                    "[--frames N] [--lease-ms MS] [--stamps pattern|realtime] [--depth-type image|string]\n");
        return 2;
    }
    Camera camera(o);
    if (!camera.start()) {
        std::fprintf(stderr, "publish_camera_dds: cannot create the DDS participant or its writers\n");
        return 1;
    }
    std::printf("publishing on domain %d\n", o.domain);
    std::fflush(stdout);
    const auto period = std::chrono::nanoseconds(kPeriodNs);
    auto next = std::chrono::steady_clock::now();
    for (std::int64_t i = 0; o.frames == 0 || i < o.frames; ++i) {
        camera.publish(i);
        next += period;
        std::this_thread::sleep_until(next);
    }
    return 0;
}
