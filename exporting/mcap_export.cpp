#include "exporting/mcap_export.h"

#include "devices/recording/frame_codec.h"
#include "exporting/ros2_messages.h"
#include "frame/camera_model.h"
#include "frame/rgb_image.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>

namespace dc::exporting {

namespace {

constexpr double kMetersPerMillimetre = 0.001;

const char* frameIdOf(McapTopic topic) {
    switch (topic) {
    case McapTopic::ColorImage:
    case McapTopic::ColorInfo:
        return "camera_color_optical_frame";
    case McapTopic::InfraredImage:
    case McapTopic::InfraredInfo:
        return "camera_infra1_optical_frame";
    default:
        return "camera_depth_optical_frame";
    }
}

ros2::Header headerOf(McapTopic topic, std::int64_t stampNs) {
    return {ros2::stampOf(stampNs), frameIdOf(topic)};
}

// The depth as whole millimetres when that loses nothing: every sample decodes back to exactly its float
// through the replay's own conversion (devices/recording's depthFromUnits, which the ROS replay uses too).
std::optional<std::vector<std::uint16_t>> millimetres(const frame::Plane<float>& depth) {
    std::vector<std::uint16_t> units(depth.pixels.size());
    for (std::size_t i = 0; i < units.size(); ++i) {
        const float v = depth.pixels[i];
        if (std::bit_cast<std::uint32_t>(v) == 0)
            continue;
        const double u = std::nearbyint(v / kMetersPerMillimetre);
        if (!(u >= 1.0 && u <= 65535.0))
            return std::nullopt;
        units[i] = static_cast<std::uint16_t>(u);
        if (std::bit_cast<std::uint32_t>(devices::recording::depthFromUnits(
                units[i], kMetersPerMillimetre)) != std::bit_cast<std::uint32_t>(v))
            return std::nullopt;
    }
    return units;
}

// An image of `channels` values of T per pixel, rows without padding.
template <class T>
ros2::Image imageOf(McapTopic topic, std::int64_t stampNs, int width, int height, int channels,
                    const char* encoding, const std::vector<T>& pixels) {
    ros2::Image image{headerOf(topic, stampNs),
                      static_cast<std::uint32_t>(height),
                      static_cast<std::uint32_t>(width),
                      encoding,
                      static_cast<std::uint32_t>(width * channels * sizeof(T)),
                      {}};
    image.data.resize(pixels.size() * sizeof(T));
    std::memcpy(image.data.data(), pixels.data(), image.data.size());
    return image;
}

ros2::Image depthImage(const frame::Plane<float>& depth, std::int64_t stampNs) {
    if (auto units = millimetres(depth))
        return imageOf(McapTopic::DepthImage, stampNs, depth.width, depth.height, 1, "16UC1", *units);
    return imageOf(McapTopic::DepthImage, stampNs, depth.width, depth.height, 1, "32FC1", depth.pixels);
}

// camera_info of a stream `width` x `height` seen through `k` (at any size) and `lens`.
ros2::CameraInfo cameraInfoOf(McapTopic topic, std::int64_t stampNs, const frame::Intrinsics& k, int width,
                              int height, const frame::Lens& lens) {
    const frame::Intrinsics at = k.width > 0 && k.height > 0 ? k.scaledTo(width, height) : k;
    ros2::CameraInfo info;
    info.header = headerOf(topic, stampNs);
    info.width = static_cast<std::uint32_t>(width);
    info.height = static_cast<std::uint32_t>(height);
    // plumb_bob is OpenCV's k1 k2 p1 p2 k3, our BrownConrady; the inverse polynomial has no ROS name, so it
    // keeps RealSense's, which depthcloud's replay reads back.
    info.distortionModel =
        lens.model == frame::LensModel::InverseBrownConrady ? "inverse_brown_conrady" : "plumb_bob";
    info.d.assign(lens.coefficients.begin(), lens.coefficients.end());
    if (lens.model == frame::LensModel::None)
        std::fill(info.d.begin(), info.d.end(), 0.0);
    info.k = {at.fx, 0, at.cx, 0, at.fy, at.cy, 0, 0, 1};
    return info;
}

ros2::TransformStamped poseTransform(const frame::Pose& pose, std::int64_t stampNs) {
    const auto& m = pose.cameraToWorld; // column-major
    ros2::TransformStamped t;
    t.header = {ros2::stampOf(stampNs), "odom"};
    t.childFrameId = frameIdOf(McapTopic::DepthImage);
    t.translation = {m[12], m[13], m[14]};
    t.rotation = ros2::quaternionOf({m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]});
    return t;
}

} // namespace

const char* topicName(McapTopic topic) {
    switch (topic) {
    case McapTopic::DepthImage:
        return "/camera/camera/depth/image_rect_raw";
    case McapTopic::DepthInfo:
        return "/camera/camera/depth/camera_info";
    case McapTopic::ColorImage:
        return "/camera/camera/color/image_raw";
    case McapTopic::ColorInfo:
        return "/camera/camera/color/camera_info";
    case McapTopic::InfraredImage:
        return "/camera/camera/infra1/image_rect_raw";
    case McapTopic::InfraredInfo:
        return "/camera/camera/infra1/camera_info";
    case McapTopic::Tf:
        return "/tf";
    case McapTopic::TfStatic:
        return "/tf_static";
    }
    return "";
}

Expected<std::unique_ptr<McapFrameWriter>> McapFrameWriter::create(const std::string& path, bool overwrite) {
    auto writer = McapWriter::create(path, {.overwrite = overwrite});
    if (!writer)
        return writer.error();
    return std::unique_ptr<McapFrameWriter>(new McapFrameWriter(std::move(*writer)));
}

std::uint16_t McapFrameWriter::channel(McapTopic topic) {
    std::uint16_t& id = channels_[static_cast<std::size_t>(topic)];
    if (id != 0)
        return id;
    const bool image =
        topic == McapTopic::DepthImage || topic == McapTopic::ColorImage || topic == McapTopic::InfraredImage;
    const std::size_t kind = topic == McapTopic::Tf || topic == McapTopic::TfStatic ? 2 : image ? 0 : 1;
    static const std::array<const ros2::MessageType*, 3> kTypes{&ros2::kImageType, &ros2::kCameraInfoType,
                                                                &ros2::kTfMessageType};
    if (schemas_[kind] == 0)
        schemas_[kind] = writer_->addSchema(kTypes[kind]->name, "ros2msg", kTypes[kind]->definition);
    id = writer_->addChannel(schemas_[kind], topicName(topic), "cdr");
    return id;
}

Status McapFrameWriter::write(McapTopic topic, std::int64_t stampNs,
                              const std::vector<std::uint8_t>& message) {
    return writer_->write(channel(topic), static_cast<std::uint64_t>(std::max<std::int64_t>(stampNs, 0)),
                          message);
}

Status McapFrameWriter::add(const frame::Frame& frame) {
    if (!frame.sceneDepth || frame.sceneDepth->depthMeters.empty())
        return Error{"frame " + std::to_string(frame.sequence) + " has no depth"};
    const std::int64_t t = frame.timestampNs;
    const auto& depth = frame.sceneDepth->depthMeters;
    const frame::Lens depthLens = frame.rig ? frame.rig->depth.lens : frame::Lens{};
    Status s = write(McapTopic::DepthImage, t, ros2::serialize(depthImage(depth, t)));
    if (s)
        s = write(McapTopic::DepthInfo, t,
                  ros2::serialize(cameraInfoOf(McapTopic::DepthInfo, t, frame.depthIntrinsics(), depth.width,
                                               depth.height, depthLens)));
    if (s)
        s = addColor(frame);
    if (s)
        s = addInfrared(frame);
    if (s && frame.pose)
        s = write(McapTopic::Tf, t, ros2::serializeTf({poseTransform(*frame.pose, t)}));
    if (s)
        s = addExtrinsics(frame);
    return s;
}

// The colour camera in the depth camera's frame: the inverse of the calibration's depth-to-colour transform
// (p_colour = R p_depth + t), so p_depth = Rᵀ (p_colour - t).
Status McapFrameWriter::addExtrinsics(const frame::Frame& frame) {
    if (extrinsicsWritten_ || !frame.rig || frame.capturedImage.empty())
        return {};
    const auto& r = frame.rig->depthToColour.rotation;
    const auto& t = frame.rig->depthToColour.translationMeters;
    ros2::TransformStamped colour;
    colour.header = headerOf(McapTopic::DepthImage, frame.timestampNs);
    colour.childFrameId = frameIdOf(McapTopic::ColorImage);
    colour.rotation = ros2::quaternionOf({r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]});
    for (int i = 0; i < 3; ++i)
        colour.translation[i] = -(r[i] * t[0] + r[3 + i] * t[1] + r[6 + i] * t[2]);
    extrinsicsWritten_ = true;
    return write(McapTopic::TfStatic, frame.timestampNs, ros2::serializeTf({colour}));
}

Status McapFrameWriter::addColor(const frame::Frame& frame) {
    if (frame.capturedImage.empty())
        return {};
    auto decoded = jpeg_.decode(frame.capturedImage);
    if (!decoded)
        return Error{"frame " + std::to_string(frame.sequence) + ": " + decoded.error().message};
    std::vector<std::uint8_t> rgb = frame::toRgb24(*decoded);
    if (rgb.empty())
        return Error{"frame " + std::to_string(frame.sequence) + ": its colour image is malformed"};
    const std::int64_t t = frame.timestampNs;
    const int w = decoded->width, h = decoded->height;
    if (Status s = write(McapTopic::ColorImage, t,
                         ros2::serialize(imageOf(McapTopic::ColorImage, t, w, h, 3, "rgb8", rgb)));
        !s)
        return s;
    const frame::Lens lens = frame.rig ? frame.rig->colour.lens : frame::Lens{};
    return write(McapTopic::ColorInfo, t,
                 ros2::serialize(cameraInfoOf(McapTopic::ColorInfo, t, frame.cameraIntrinsics, w, h, lens)));
}

Status McapFrameWriter::addInfrared(const frame::Frame& frame) {
    if (!frame.infrared || frame.infrared->empty())
        return {};
    const auto& ir = *frame.infrared;
    const std::int64_t t = frame.timestampNs;
    const bool narrow =
        std::all_of(ir.pixels.begin(), ir.pixels.end(), [](std::uint16_t v) { return v < 256; });
    ros2::Image image;
    if (narrow) {
        const std::vector<std::uint8_t> bytes(ir.pixels.begin(), ir.pixels.end());
        image = imageOf(McapTopic::InfraredImage, t, ir.width, ir.height, 1, "mono8", bytes);
    } else {
        image = imageOf(McapTopic::InfraredImage, t, ir.width, ir.height, 1, "mono16", ir.pixels);
    }
    if (Status s = write(McapTopic::InfraredImage, t, ros2::serialize(image)); !s)
        return s;
    const frame::Lens lens = frame.rig ? frame.rig->depth.lens : frame::Lens{};
    return write(McapTopic::InfraredInfo, t,
                 ros2::serialize(cameraInfoOf(McapTopic::InfraredInfo, t, frame.depthIntrinsics(), ir.width,
                                              ir.height, lens)));
}

} // namespace dc::exporting
