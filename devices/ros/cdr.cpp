#include "devices/ros/cdr.h"

#include "devices/ros/compressed_image.h"
#include "devices/ros/ros_image.h"

#include <bit>
#include <cstring>

namespace dc::devices::ros {

namespace {

// The encapsulation identifiers of plain CDR (XCDR1); parameter lists and XCDR2 are not what ROS 2 writes
// for these messages.
constexpr std::uint8_t kCdrBigEndian = 0x00;
constexpr std::uint8_t kCdrLittleEndian = 0x01;

} // namespace

CdrReader::CdrReader(std::span<const std::uint8_t> message) : data_(message) {
    if (message.size() < 4 || message[0] != 0 ||
        (message[1] != kCdrBigEndian && message[1] != kCdrLittleEndian)) {
        fail(message.size() < 4 ? "shorter than CDR's encapsulation header"
                                : "not plain CDR (encapsulation " + std::to_string(message[0]) + "," +
                                      std::to_string(message.size() > 1 ? message[1] : 0) + ")");
        return;
    }
    bigEndian_ = message[1] == kCdrBigEndian;
}

void CdrReader::fail(const std::string& why) {
    if (!failed_)
        problem_ = why;
    failed_ = true;
}

// Moves past the padding that aligns a value of `alignment` bytes, then past `size` bytes.
bool CdrReader::take(std::size_t size, std::size_t alignment) {
    if (failed_)
        return false;
    const std::size_t padding = (alignment - (pos_ - 4) % alignment) % alignment;
    if (padding > data_.size() - pos_ || size > data_.size() - pos_ - padding) {
        fail("ends at byte " + std::to_string(data_.size()) + " inside a field at byte " +
             std::to_string(pos_));
        return false;
    }
    pos_ += padding + size;
    return true;
}

std::uint64_t CdrReader::swapped(std::uint64_t v, std::size_t size) const {
    if (bigEndian_ == (std::endian::native == std::endian::big))
        return v;
    std::uint64_t out = 0;
    for (std::size_t i = 0; i < size; ++i)
        out |= ((v >> (8 * i)) & 0xff) << (8 * (size - 1 - i));
    return out;
}

std::uint8_t CdrReader::u8() {
    return take(1, 1) ? data_[pos_ - 1] : 0;
}

std::uint32_t CdrReader::u32() {
    std::uint32_t v = 0;
    if (take(4, 4))
        std::memcpy(&v, data_.data() + pos_ - 4, 4);
    return static_cast<std::uint32_t>(swapped(v, 4));
}

double CdrReader::f64() {
    std::uint64_t v = 0;
    if (take(8, 8))
        std::memcpy(&v, data_.data() + pos_ - 8, 8);
    return std::bit_cast<double>(swapped(v, 8));
}

// A CDR string counts its terminating NUL; the value leaves it out.
std::string CdrReader::string() {
    const auto b = bytes();
    if (b.empty())
        return {};
    return {b.begin(), b.end() - (b.back() == 0 ? 1 : 0)};
}

std::span<const std::uint8_t> CdrReader::bytes() {
    const std::uint32_t n = u32();
    if (!take(n, 1))
        return {};
    return data_.subspan(pos_ - n, n);
}

std::int64_t CdrReader::stampNs() {
    const std::int64_t seconds = i32();
    return seconds * 1'000'000'000 + u32();
}

namespace {

Error problemOf(const CdrReader& cdr, const char* type) {
    return Error{std::string("a ") + type + " message is unreadable: " + cdr.problem()};
}

} // namespace

Expected<std::int64_t> decodeHeaderStampNs(std::span<const std::uint8_t> message) {
    CdrReader cdr(message);
    const std::int64_t ns = cdr.stampNs();
    if (cdr.failed())
        return problemOf(cdr, "header");
    return ns;
}

Expected<RosImage> decodeImage(std::span<const std::uint8_t> message) {
    CdrReader cdr(message);
    RosImage image;
    image.stampNs = cdr.stampNs();
    image.frameId = cdr.string();
    image.height = cdr.u32();
    image.width = cdr.u32();
    image.encoding = cdr.string();
    image.bigEndian = cdr.u8() != 0;
    image.step = cdr.u32();
    const auto data = cdr.bytes();
    if (cdr.failed())
        return problemOf(cdr, "sensor_msgs/msg/Image");
    image.data.assign(data.begin(), data.end());
    return image;
}

Expected<RosImage> decodeCompressedImage(std::span<const std::uint8_t> message) {
    CdrReader cdr(message);
    const std::int64_t stampNs = cdr.stampNs();
    std::string frameId = cdr.string();
    const std::string format = cdr.string();
    const auto data = cdr.bytes();
    if (cdr.failed())
        return problemOf(cdr, "sensor_msgs/msg/CompressedImage");
    auto image = decompressImage(format, data.data(), data.size());
    if (!image)
        return image.error();
    image->stampNs = stampNs;
    image->frameId = std::move(frameId);
    return image;
}

ImageDecoder imageDecoderFor(const std::string& type) {
    return type == kRosCompressedImageType ? decodeCompressedImage : decodeImage;
}

Expected<RosCameraInfo> decodeCameraInfo(std::span<const std::uint8_t> message) {
    CdrReader cdr(message);
    RosCameraInfo info;
    cdr.stampNs();
    cdr.string(); // frame_id
    info.height = cdr.u32();
    info.width = cdr.u32();
    info.distortionModel = cdr.string();
    const std::uint32_t count = cdr.u32();
    // Each coefficient takes 8 bytes: a count beyond the message is damage, not a reason to allocate.
    if (count > message.size() / 8)
        return Error{"a sensor_msgs/msg/CameraInfo message is unreadable: " + std::to_string(count) +
                     " distortion coefficients in " + std::to_string(message.size()) + " bytes"};
    for (std::uint32_t i = 0; i < count; ++i)
        info.d.push_back(cdr.f64());
    for (double& k : info.k)
        k = cdr.f64();
    if (cdr.failed())
        return problemOf(cdr, "sensor_msgs/msg/CameraInfo");
    return info;
}

Expected<std::vector<RosTransformStamped>> decodeTfMessage(std::span<const std::uint8_t> message) {
    CdrReader cdr(message);
    const std::uint32_t count = cdr.u32();
    // A transform takes at least 80 bytes (a stamp, two empty names, seven doubles): a count beyond the
    // message is damage, not a reason to allocate.
    constexpr std::size_t kSmallestTransform = 80;
    if (count > message.size() / kSmallestTransform)
        return Error{"a tf2_msgs/msg/TFMessage message is unreadable: " + std::to_string(count) +
                     " transforms in " + std::to_string(message.size()) + " bytes"};
    std::vector<RosTransformStamped> transforms(count);
    for (RosTransformStamped& t : transforms) {
        t.stampNs = cdr.stampNs();
        t.parentFrameId = cdr.string();
        t.childFrameId = cdr.string();
        for (double& v : t.transform.translationMeters)
            v = cdr.f64();
        for (double& v : t.transform.rotationXyzw)
            v = cdr.f64();
    }
    if (cdr.failed())
        return problemOf(cdr, "tf2_msgs/msg/TFMessage");
    return transforms;
}

} // namespace dc::devices::ros
