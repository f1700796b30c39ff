#include "exporting/ros2_messages.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <span>
#include <type_traits>

namespace dc::exporting::ros2 {

namespace {

// Little-endian XCDR1: each primitive aligned to its own size, counted from the end of the encapsulation
// header; strings are a uint32 length that counts their terminating NUL, then the bytes and the NUL;
// sequences a uint32 element count, then the elements; fixed arrays the elements alone.
class CdrWriter {
public:
    CdrWriter() : out_{0x00, 0x01, 0x00, 0x00} {} // CDR_LE, no options

    template <class T> void put(T value) {
        static_assert(std::is_arithmetic_v<T>);
        static_assert(std::endian::native == std::endian::little, "CDR_LE is written as the host stores it");
        align(sizeof(T));
        const std::size_t at = out_.size();
        out_.resize(at + sizeof(T));
        std::memcpy(out_.data() + at, &value, sizeof(T));
    }
    void string(const std::string& s) {
        put(static_cast<std::uint32_t>(s.size() + 1));
        out_.insert(out_.end(), s.begin(), s.end());
        out_.push_back(0);
    }
    void bytes(std::span<const std::uint8_t> data) {
        put(static_cast<std::uint32_t>(data.size()));
        out_.insert(out_.end(), data.begin(), data.end());
    }
    void doubles(std::span<const double> values) {
        for (const double v : values)
            put(v);
    }
    void header(const Header& h) {
        put(h.stamp.sec);
        put(h.stamp.nanosec);
        string(h.frameId);
    }
    std::vector<std::uint8_t> take() { return std::move(out_); }

private:
    static constexpr std::size_t kEncapsulationBytes = 4;
    void align(std::size_t size) {
        const std::size_t offset = out_.size() - kEncapsulationBytes;
        out_.resize(out_.size() + (size - offset % size) % size, 0);
    }

    std::vector<std::uint8_t> out_;
};

} // namespace

Stamp stampOf(std::int64_t ns) {
    ns = std::max<std::int64_t>(ns, 0);
    return {static_cast<std::int32_t>(ns / 1'000'000'000), static_cast<std::uint32_t>(ns % 1'000'000'000)};
}

std::vector<std::uint8_t> serialize(const Image& image) {
    CdrWriter w;
    w.header(image.header);
    w.put(image.height);
    w.put(image.width);
    w.string(image.encoding);
    w.put(std::uint8_t{0}); // is_bigendian: the pixels are little-endian
    w.put(image.step);
    w.bytes(image.data);
    return w.take();
}

std::vector<std::uint8_t> serialize(const CameraInfo& info) {
    CdrWriter w;
    w.header(info.header);
    w.put(info.height);
    w.put(info.width);
    w.string(info.distortionModel);
    w.put(static_cast<std::uint32_t>(info.d.size()));
    w.doubles(info.d);
    w.doubles(info.k);
    const std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
    w.doubles(r);
    const auto& k = info.k;
    const std::array<double, 12> p{k[0], k[1], k[2], 0, k[3], k[4], k[5], 0, k[6], k[7], k[8], 0};
    w.doubles(p);
    w.put(std::uint32_t{0}); // binning_x, binning_y: none
    w.put(std::uint32_t{0});
    for (int i = 0; i < 4; ++i) // roi: x_offset y_offset height width all 0, the whole image
        w.put(std::uint32_t{0});
    w.put(std::uint8_t{0}); // do_rectify
    return w.take();
}

std::vector<std::uint8_t> serializeTf(const std::vector<TransformStamped>& transforms) {
    CdrWriter w;
    w.put(static_cast<std::uint32_t>(transforms.size()));
    for (const TransformStamped& t : transforms) {
        w.header(t.header);
        w.string(t.childFrameId);
        w.doubles(t.translation);
        w.doubles(t.rotation);
    }
    return w.take();
}

std::array<double, 4> quaternionOf(const std::array<double, 9>& m) {
    // Shepperd's method: divide by the largest of the four candidates, so no branch loses precision.
    const double trace = m[0] + m[4] + m[8];
    std::array<double, 4> q{}; // x y z w
    if (trace >= m[0] && trace >= m[4] && trace >= m[8]) {
        const double s = 2.0 * std::sqrt(1.0 + trace);
        q = {(m[7] - m[5]) / s, (m[2] - m[6]) / s, (m[3] - m[1]) / s, 0.25 * s};
    } else if (m[0] >= m[4] && m[0] >= m[8]) {
        const double s = 2.0 * std::sqrt(1.0 + m[0] - m[4] - m[8]);
        q = {0.25 * s, (m[1] + m[3]) / s, (m[2] + m[6]) / s, (m[7] - m[5]) / s};
    } else if (m[4] >= m[8]) {
        const double s = 2.0 * std::sqrt(1.0 + m[4] - m[0] - m[8]);
        q = {(m[1] + m[3]) / s, 0.25 * s, (m[5] + m[7]) / s, (m[2] - m[6]) / s};
    } else {
        const double s = 2.0 * std::sqrt(1.0 + m[8] - m[0] - m[4]);
        q = {(m[2] + m[6]) / s, (m[5] + m[7]) / s, 0.25 * s, (m[3] - m[1]) / s};
    }
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q)
        c /= norm;
    return q;
}

// The definitions as ROS 2 Humble ships them, comments left out.
#define DC_ROS2_SEPARATOR "================================================================================\n"
#define DC_ROS2_HEADER                                                                                       \
    DC_ROS2_SEPARATOR "MSG: std_msgs/Header\n"                                                               \
                      "builtin_interfaces/Time stamp\n"                                                      \
                      "string frame_id\n" DC_ROS2_SEPARATOR "MSG: builtin_interfaces/Time\n"                 \
                      "int32 sec\n"                                                                          \
                      "uint32 nanosec\n"

const MessageType kImageType{"sensor_msgs/msg/Image", "std_msgs/Header header\n"
                                                      "uint32 height\n"
                                                      "uint32 width\n"
                                                      "string encoding\n"
                                                      "uint8 is_bigendian\n"
                                                      "uint32 step\n"
                                                      "uint8[] data\n" DC_ROS2_HEADER};

const MessageType kCameraInfoType{"sensor_msgs/msg/CameraInfo",
                                  "std_msgs/Header header\n"
                                  "uint32 height\n"
                                  "uint32 width\n"
                                  "string distortion_model\n"
                                  "float64[] d\n"
                                  "float64[9] k\n"
                                  "float64[9] r\n"
                                  "float64[12] p\n"
                                  "uint32 binning_x\n"
                                  "uint32 binning_y\n"
                                  "RegionOfInterest roi\n" DC_ROS2_HEADER DC_ROS2_SEPARATOR
                                  "MSG: sensor_msgs/RegionOfInterest\n"
                                  "uint32 x_offset\n"
                                  "uint32 y_offset\n"
                                  "uint32 height\n"
                                  "uint32 width\n"
                                  "bool do_rectify\n"};

const MessageType kTfMessageType{
    "tf2_msgs/msg/TFMessage",
    "geometry_msgs/TransformStamped[] transforms\n" DC_ROS2_SEPARATOR "MSG: geometry_msgs/TransformStamped\n"
    "std_msgs/Header header\n"
    "string child_frame_id\n"
    "Transform transform\n" DC_ROS2_HEADER DC_ROS2_SEPARATOR "MSG: geometry_msgs/Transform\n"
    "Vector3 translation\n"
    "Quaternion rotation\n" DC_ROS2_SEPARATOR "MSG: geometry_msgs/Vector3\n"
    "float64 x\n"
    "float64 y\n"
    "float64 z\n" DC_ROS2_SEPARATOR "MSG: geometry_msgs/Quaternion\n"
    "float64 x 0\n"
    "float64 y 0\n"
    "float64 z 0\n"
    "float64 w 1\n"};

#undef DC_ROS2_HEADER
#undef DC_ROS2_SEPARATOR

} // namespace dc::exporting::ros2
