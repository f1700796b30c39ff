#include "devices/ros/bag_source.h"

#include "devices/replay/tum_format.h"
#include "devices/ros/bag_reader.h"
#include "devices/ros/tf_tree.h"
#include "frame/calibration.h"
#include "frame/camera_model.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace dc::devices::ros {

namespace {

// A RealSense stream's topics share a prefix: <prefix>/image/data, <prefix>/info/camera_info, <prefix>/tf/N.
std::optional<std::string> realsensePrefix(const std::string& imageTopic) {
    const std::string suffix = "/image/data";
    if (!imageTopic.ends_with(suffix) || !imageTopic.starts_with("/device_"))
        return std::nullopt;
    return imageTopic.substr(0, imageTopic.size() - suffix.size());
}

// camera_info beside an image topic: RealSense's info/camera_info, or the namespace's camera_info as ROS
// camera drivers publish it (/camera/depth/image_rect_raw -> /camera/depth/camera_info).
std::string cameraInfoTopic(const std::string& imageTopic) {
    if (auto prefix = realsensePrefix(imageTopic))
        return *prefix + "/info/camera_info";
    const std::string raw = withoutTransport(imageTopic);
    return raw.substr(0, raw.rfind('/')) + "/camera_info";
}

bool isCompressedImageTopic(const MessageStore::Topic& topic) {
    return topic.type == kRosCompressedImageType;
}

bool isImageTopic(const MessageStore::Topic& topic) {
    return topic.type == kRosImageType || isCompressedImageTopic(topic);
}

// librealsense records each stream's extrinsics to a reference stream as <prefix>/tf/<reference>: a point
// in the stream's frame maps to the reference's as p_ref = R p + t. Depth -> colour goes through it:
// p_color = Rc^T (Rd p + td - tc).
BagExtrinsics depthToColor(const RosTransform& depth, const RosTransform& color) {
    const auto rd = frame::rotationFromQuaternion(depth.rotationXyzw);
    const auto rc = frame::rotationFromQuaternion(color.rotationXyzw);
    BagExtrinsics out;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double r = 0.0;
            for (int k = 0; k < 3; ++k)
                r += rc[k * 3 + i] * rd[k * 3 + j];
            out.rotation[i * 3 + j] = r;
        }
        double t = 0.0;
        for (int k = 0; k < 3; ++k)
            t += rc[k * 3 + i] * (depth.translationMeters[k] - color.translationMeters[k]);
        out.translationMeters[i] = t;
    }
    return out;
}

// A camera_info's lens as registration models it: plumb_bob and RealSense's Brown Conrady are OpenCV's
// polynomial; RealSense's Inverse Brown Conrady runs it the other way. All-zero coefficients are no lens.
// Another model (equidistant, rational) is left out, and the calibration is marked approximate.
frame::Lens lensOf(const CameraInfoRecord& info, bool& approximate) {
    frame::Lens lens;
    const bool bent =
        std::any_of(info.distortion.begin(), info.distortion.end(), [](double d) { return d != 0.0; });
    if (!bent)
        return lens;
    std::string model = info.distortionModel;
    std::transform(model.begin(), model.end(), model.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (info.distortion.size() < 5 || model.find("equidistant") != std::string::npos ||
        model.find("rational") != std::string::npos) {
        approximate = true;
        return lens;
    }
    lens.model = model.find("inverse") != std::string::npos ? frame::LensModel::InverseBrownConrady
                                                            : frame::LensModel::BrownConrady;
    std::copy_n(info.distortion.begin(), 5, lens.coefficients.begin());
    return lens;
}

// The two-sensor calibration a RealSense bag records: both streams' camera_info and the transform between
// them. Without all three the colour is taken as one camera's, as for any other replay.
std::shared_ptr<const frame::RigCalibration> rigCalibration(const BagRig& rig, const std::string& path) {
    if (!rig.depth || !rig.color || !rig.depthToColor)
        return nullptr;
    frame::RigCalibration out;
    out.depth = {rig.depth->intrinsics, lensOf(*rig.depth, out.approximate)};
    out.colour = {rig.color->intrinsics, lensOf(*rig.color, out.approximate)};
    out.depthToColour = {rig.depthToColor->rotation, rig.depthToColor->translationMeters};
    out.name = std::filesystem::path(path).filename().string() + " (recorded)";
    return std::make_shared<const frame::RigCalibration>(std::move(out));
}

// How much a topic's name says it is the depth sensor's infrared stream: RealSense's Infrared_N first,
// then the words drivers use ("infra1", "ir/image_raw"); -1 for neither.
int infraredRank(const std::string& topic) {
    if (topic.find("/Infrared_") != std::string::npos)
        return 0;
    std::string lower = topic;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (lower.find("infra") != std::string::npos || lower.find("/ir/") != std::string::npos ||
        lower.find("/ir_") != std::string::npos)
        return 1;
    return -1;
}

// A camera's place in its tf root as a camera-to-world pose (ROS's optical frames have OpenCV's axes, as
// ours), column-major.
frame::Pose poseOf(const frame::RigidTransform& t) {
    frame::Pose pose;
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col)
            pose.cameraToWorld[col * 4 + row] = t.rotation[row * 3 + col];
        pose.cameraToWorld[12 + row] = t.translationMeters[row];
    }
    return pose;
}

// How far from a depth image's stamp a moving tf link that places it may be stamped: a frame at 20 fps.
constexpr std::int64_t kPoseToleranceNs = 50'000'000;
constexpr const char* kTfType = "tf2_msgs/TFMessage";

// One image topic's messages with the timestamps replay uses.
struct ImageStream {
    std::size_t handle = 0;
    std::vector<std::int64_t> timestampsNs;
};

class BagSource final : public replay::ReplaySource {
public:
    BagSource(std::unique_ptr<MessageStore> store, std::string path, BagOptions options)
        : path_(std::move(path)), options_(std::move(options)), bag_(std::move(store)) {}

    Status open(std::vector<std::string> warnings);

    std::string description() const override {
        return bag_->formatName() + " " + std::filesystem::path(path_).filename().string() + " (" +
               depthTopic_ + (colorTopic_.empty() ? "" : ", " + colorTopic_) +
               (infraredTopic_.empty() ? "" : ", infrared " + infraredTopic_) + ")";
    }
    Capabilities capabilities() const override {
        return {.sceneDepth = true,
                .color = !colorTopic_.empty(),
                .pose = !poses_.empty(),
                .approximateIntrinsics = !rig_.depth};
    }
    std::size_t frameCount() const override { return depth_.timestampsNs.size(); }
    std::int64_t timestampNs(std::size_t i) const override { return depth_.timestampsNs[i]; }
    Expected<frame::Frame> frame(std::size_t i) override;
    std::vector<std::string> warnings() const override { return warnings_; }
    void setDecodeColor(bool decode) override { decodeColor_ = decode; }

    const BagRig& rig() const { return rig_; }

private:
    Status chooseTopics();
    Status checkTopic(const std::string& topic, ImageKind want, const char* what) const;
    Expected<ImageStream> index(const std::string& topic);
    void readCalibration();
    void chooseInfrared();
    void readTf();
    void extrinsicsFromTf();
    void readPoses();
    std::vector<std::optional<std::size_t>> pairWithDepth(const ImageStream& other) const;

    std::string path_;
    BagOptions options_;
    std::unique_ptr<MessageStore> bag_;
    std::string depthTopic_, colorTopic_, infraredTopic_;
    ImageStream depth_, color_, infrared_;
    std::vector<std::optional<std::size_t>> colorOf_, infraredOf_; // per depth image
    std::vector<std::optional<frame::Pose>> poses_;                // per depth image, from tf
    TfTree tf_;
    double metersPerUnit_ = kRosDepthMetersPerUnit;
    BagRig rig_;
    std::shared_ptr<const frame::RigCalibration> rigCalibration_; // when the bag records both sensors
    std::vector<std::string> warnings_;
    bool decodeColor_ = true;
};

ImageKind kindOf(const MessageStore& bag, const std::string& topic) {
    const auto image = bag.firstImage(topic);
    return image ? imageKind(image->encoding) : ImageKind::Other;
}

Status BagSource::checkTopic(const std::string& topic, ImageKind want, const char* what) const {
    const auto& topics = bag_->topics();
    const auto found = std::find_if(topics.begin(), topics.end(),
                                    [&](const MessageStore::Topic& t) { return t.name == topic; });
    if (found == topics.end())
        return Error{path_ + " has no topic " + topic};
    if (!isImageTopic(*found))
        return Error{path_ + ": topic " + topic + " is " + found->type + ", not " + kRosImageType + " or " +
                     kRosCompressedImageType};
    if (const auto image = bag_->firstImage(topic); !image || imageKind(image->encoding) != want)
        return Error{path_ + ": topic " + topic + " is not a " + what + " image (encoding '" +
                     (image ? image->encoding : "unreadable") + "')"};
    return {};
}

Status BagSource::chooseTopics() {
    // RealSense's ROS 1 recordings name their streams; other bags are ranked by the words their drivers use.
    // ROS 2 wrappers' aligned_depth_to_color comes before their plain depth: its pixels are the colour
    // image's, so colour is exact without the extrinsics a ROS 2 recording keeps only in tf.
    auto rank = [](const std::string& topic, ImageKind kind) {
        const bool depth = kind == ImageKind::Depth;
        if (topic.find(depth ? "/Depth_" : "/Color_") != std::string::npos)
            return 0;
        if (depth && topic.find("aligned_depth_to_color") != std::string::npos)
            return 1;
        return topic.find(depth ? "depth" : "color") != std::string::npos ? 2 : 3;
    };
    // Of one rank, a raw image comes before a compressed one (JPEG loses detail; both are often recorded).
    std::vector<std::pair<int, std::string>> depths, colours;
    for (const MessageStore::Topic& t : bag_->topics()) {
        if (!isImageTopic(t))
            continue;
        const ImageKind kind = kindOf(*bag_, t.name);
        const int order = 2 * rank(t.name, kind) + (isCompressedImageTopic(t) ? 1 : 0);
        if (kind == ImageKind::Depth)
            depths.emplace_back(order, t.name);
        else if (kind == ImageKind::Color)
            colours.emplace_back(order, t.name);
    }
    std::sort(depths.begin(), depths.end());
    std::sort(colours.begin(), colours.end());
    // Topics the user names are all there is: a depth topic alone replays without colour.
    const bool chosen = !options_.depthTopic.empty();
    depthTopic_ = chosen || depths.empty() ? options_.depthTopic : depths.front().second;
    colorTopic_ = chosen || colours.empty() ? options_.colorTopic : colours.front().second;
    if (depthTopic_.empty())
        return Error{path_ + " has no depth image topic (sensor_msgs/Image in 16UC1, mono16 or 32FC1)"};
    if (Status s = checkTopic(depthTopic_, ImageKind::Depth, "depth"); !s)
        return s;
    if (!colorTopic_.empty())
        return checkTopic(colorTopic_, ImageKind::Color, "colour");
    return {};
}

Expected<ImageStream> BagSource::index(const std::string& topic) {
    auto handle = bag_->indexTopic(topic);
    if (!handle)
        return handle.error();
    ImageStream stream{*handle, {}};
    std::size_t backwards = 0;
    for (std::size_t i = 0; i < bag_->messageCount(*handle); ++i) {
        // Header stamps are the sensor's clock (what a live subscriber sees); a driver that leaves them
        // zero gets the recording time.
        auto stamp = bag_->imageStampNs(*handle, i);
        if (!stamp)
            return Error{path_ + ": " + stamp.error().message};
        std::int64_t ns = *stamp != 0 ? *stamp : bag_->recordedNs(*handle, i);
        // Replay needs non-decreasing time: a stamp that jumps back keeps the one before it.
        if (!stream.timestampsNs.empty() && ns < stream.timestampsNs.back()) {
            ns = stream.timestampsNs.back();
            ++backwards;
        }
        stream.timestampsNs.push_back(ns);
    }
    if (backwards > 0)
        warnings_.push_back(path_ + ": " + std::to_string(backwards) + " images on " + topic +
                            " are stamped before the one recorded ahead of them; they keep its time");
    return stream;
}

void BagSource::readCalibration() {
    if (auto info = bag_->firstCameraInfo(cameraInfoTopic(depthTopic_))) {
        if (auto record = cameraInfoRecord(*info))
            rig_.depth = *record;
        else
            warnings_.push_back(path_ + ": depth " + record.error().message);
    }
    if (!colorTopic_.empty())
        if (auto info = bag_->firstCameraInfo(cameraInfoTopic(colorTopic_)))
            if (auto record = cameraInfoRecord(*info))
                rig_.color = *record;
    const auto depthPrefix = realsensePrefix(depthTopic_);
    if (depthPrefix) {
        // /device_0/sensor_0/Depth_0 -> /device_0/sensor_0/option/Depth Units/value
        const std::string sensor = depthPrefix->substr(0, depthPrefix->rfind('/'));
        if (auto units = bag_->firstFloat32(sensor + "/option/Depth Units/value"); units && *units > 0.0f)
            metersPerUnit_ = *units;
    }
    const auto colorPrefix = realsensePrefix(colorTopic_);
    if (depthPrefix && colorPrefix) {
        auto depthTf = bag_->firstTransform(*depthPrefix + "/tf/0");
        auto colorTf = bag_->firstTransform(*colorPrefix + "/tf/0");
        if (depthTf && colorTf)
            rig_.depthToColor = depthToColor(*depthTf, *colorTf);
    }
    if (!rig_.depthToColor)
        extrinsicsFromTf();
    if (!rig_.depth)
        warnings_.push_back(path_ + ": no camera_info for " + depthTopic_ + " (looked for " +
                            cameraInfoTopic(depthTopic_) + "); the cloud's geometry is approximate");
    rigCalibration_ = rigCalibration(rig_, path_);
}

// The infrared stream is found by name and encoding whatever topics were chosen: it only adds a plane.
void BagSource::chooseInfrared() {
    int best = 2;
    for (const MessageStore::Topic& t : bag_->topics()) {
        const int rank = infraredRank(t.name);
        if (!isImageTopic(t) || t.name == depthTopic_ || rank < 0 || rank >= best)
            continue;
        if (const auto image = bag_->firstImage(t.name); image && isInfraredEncoding(image->encoding)) {
            infraredTopic_ = t.name;
            best = rank;
        }
    }
}

// For each depth image, the other stream's image nearest in time within the pairing tolerance.
std::vector<std::optional<std::size_t>> BagSource::pairWithDepth(const ImageStream& other) const {
    std::vector<double> depthTimes, otherTimes;
    for (std::int64_t ns : depth_.timestampsNs)
        depthTimes.push_back(ns * 1e-9);
    for (std::int64_t ns : other.timestampsNs)
        otherTimes.push_back(ns * 1e-9);
    std::vector<std::optional<std::size_t>> out(depthTimes.size());
    for (auto [d, o] : replay::associateByTimestamp(depthTimes, otherTimes, options_.maxPairGapSeconds))
        out[d] = o;
    return out;
}

Status BagSource::open(std::vector<std::string> warnings) {
    warnings_ = std::move(warnings);
    for (std::string& w : bag_->warnings())
        warnings_.push_back(std::move(w));
    if (Status s = chooseTopics(); !s)
        return s;
    readTf();
    readCalibration();
    auto depth = index(depthTopic_);
    if (!depth)
        return depth.error();
    depth_ = std::move(*depth);
    if (!colorTopic_.empty()) {
        auto color = index(colorTopic_);
        if (!color)
            return color.error();
        color_ = std::move(*color);
    }
    colorOf_ = pairWithDepth(color_);
    chooseInfrared();
    if (!infraredTopic_.empty()) {
        auto infrared = index(infraredTopic_);
        if (!infrared)
            return infrared.error();
        infrared_ = std::move(*infrared);
    }
    infraredOf_ = pairWithDepth(infrared_);
    readPoses();
    return {};
}

// Every transform on /tf and /tf_static, for poses and extrinsics. A message that cannot be read is
// skipped and counted in one warning.
void BagSource::readTf() {
    if (!bag_->readsTransforms())
        return;
    for (const MessageStore::Topic& topic : bag_->topics()) {
        const bool fixed = topic.name == "/tf_static";
        if (topic.type != kTfType || (topic.name != "/tf" && !fixed))
            continue;
        auto handle = bag_->indexTopic(topic.name);
        if (!handle)
            continue;
        std::size_t unreadable = 0;
        for (std::size_t i = 0; i < bag_->messageCount(*handle); ++i) {
            auto transforms = bag_->transforms(*handle, i);
            unreadable += transforms ? 0 : 1;
            if (transforms)
                for (const RosTransformStamped& t : *transforms)
                    tf_.add(t, fixed);
        }
        if (unreadable > 0)
            warnings_.push_back(path_ + ": " + std::to_string(unreadable) + " " + topic.name +
                                " messages could not be read; the transforms they held are left out");
    }
    tf_.finish();
}

// A ROS 2 recording keeps the colour camera's place only in tf: where both images' frames meet in one root,
// the depth-to-colour transform follows (p_colour = C⁻¹ D p_depth), at the first depth image's stamp.
void BagSource::extrinsicsFromTf() {
    const auto depth = bag_->firstImage(depthTopic_);
    const auto colour = colorTopic_.empty() ? std::nullopt : bag_->firstImage(colorTopic_);
    if (tf_.empty() || !depth || !colour || depth->frameId.empty() || depth->frameId == colour->frameId)
        return;
    const auto d = tf_.locate(depth->frameId, depth->stampNs, kPoseToleranceNs);
    const auto c = tf_.locate(colour->frameId, depth->stampNs, kPoseToleranceNs);
    if (!d || !c || d->root != c->root)
        return;
    const frame::RigidTransform depthToColour = frame::compose(frame::inverse(c->toRoot), d->toRoot);
    rig_.depthToColor = BagExtrinsics{depthToColour.rotation, depthToColour.translationMeters};
}

// Where a ROS 2 recording places its depth camera (our MCAP export's odom -> camera_depth_optical_frame, a
// SLAM node's map -> camera_link with the driver's fixed links below it): the depth image's frame_id
// followed up its tf chain at the image's stamp. A chain without a moving link gives no pose: it says
// where the camera is mounted, not where it went.
void BagSource::readPoses() {
    const auto image = bag_->firstImage(depthTopic_);
    if (tf_.empty() || !image || image->frameId.empty())
        return;
    std::vector<std::optional<frame::Pose>> poses(frameCount());
    bool any = false;
    for (std::size_t i = 0; i < frameCount(); ++i)
        if (const auto located = tf_.locate(image->frameId, depth_.timestampsNs[i], kPoseToleranceNs);
            located && located->moving) {
            poses[i] = poseOf(located->toRoot);
            any = true;
        }
    if (any)
        poses_ = std::move(poses);
}

Expected<frame::Frame> BagSource::frame(std::size_t i) {
    auto fail = [&](const Error& e) {
        return Error{path_ + ": frame " + std::to_string(i) + ": " + e.message};
    };
    frame::Frame frame;
    frame.sequence = i;
    frame.timestampNs = depth_.timestampsNs[i];
    if (i < poses_.size())
        frame.pose = poses_[i];
    auto depthImage = bag_->image(depth_.handle, i);
    if (!depthImage)
        return fail(depthImage.error());
    auto depth = depthFromImage(*depthImage, metersPerUnit_);
    if (!depth)
        return fail(depth.error());
    // With the recorded calibration of both sensors the frame carries it: the depth map unprojects with the
    // depth sensor's intrinsics, and each point takes its colour where the colour sensor sees it. Without,
    // the image intrinsics are the depth camera's at the colour image's size: geometry exact, colour as one
    // camera's.
    frame.rig = rigCalibration_;
    const frame::Intrinsics depthK =
        rig_.depth ? rig_.depth->intrinsics
                   : frame::intrinsicsFromFieldOfView(depth->width, depth->height, kRosFallbackFovDegrees);
    frame.cameraIntrinsics = depthK.scaledTo(depth->width, depth->height);
    frame.sceneDepth = frame::DepthData{std::move(*depth), {}};
    if (decodeColor_ && colorOf_[i]) {
        auto colorImage = bag_->image(color_.handle, *colorOf_[i]);
        if (!colorImage)
            return fail(colorImage.error());
        auto color = colorFromImage(*colorImage);
        if (!color)
            return fail(color.error());
        frame.cameraIntrinsics =
            (rigCalibration_ ? rig_.color->intrinsics : depthK).scaledTo(color->width, color->height);
        frame.capturedImage = std::move(*color);
    }
    if (infraredOf_[i]) {
        auto infraredImage = bag_->image(infrared_.handle, *infraredOf_[i]);
        if (!infraredImage)
            return fail(infraredImage.error());
        auto infrared = infraredFromImage(*infraredImage);
        if (!infrared)
            return fail(infrared.error());
        frame.infrared = std::move(*infrared);
    }
    return frame;
}

} // namespace

Expected<std::unique_ptr<replay::ReplaySource>> openMessageSource(std::unique_ptr<MessageStore> store,
                                                                  const std::string& path,
                                                                  const BagOptions& options,
                                                                  std::vector<std::string> warnings) {
    auto source = std::make_unique<BagSource>(std::move(store), path, options);
    if (Status s = source->open(std::move(warnings)); !s)
        return s.error();
    return std::unique_ptr<replay::ReplaySource>(std::move(source));
}

Expected<std::unique_ptr<replay::ReplaySource>> openBagSource(const std::string& path,
                                                              const BagOptions& options) {
    auto bag = BagReader::open(path);
    if (!bag)
        return bag.error();
    return openMessageSource(std::move(*bag), path, options);
}

const BagRig* bagRig(const replay::ReplaySource& source) {
    const auto* bag = dynamic_cast<const BagSource*>(&source);
    return bag ? &bag->rig() : nullptr;
}

} // namespace dc::devices::ros
