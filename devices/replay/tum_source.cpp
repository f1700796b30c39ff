#include "devices/replay/capture_files.h"
#include "devices/replay/importers.h"
#include "devices/replay/tum_format.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace dc::devices::replay {

namespace {

namespace fs = std::filesystem;

// TUM stores depth as uint16 at 5000 units per meter.
constexpr double kMetersPerUnit = 1.0 / 5000.0;
// The benchmark's default intrinsics (PrimeSense defaults, ROS's "fr0"), used without a calibration.
constexpr frame::Intrinsics kDefaultIntrinsics{525.0, 525.0, 319.5, 239.5, 640, 480};

class TumSource final : public ReplaySource {
public:
    TumSource(fs::path dir, TumOptions options) : dir_(std::move(dir)), options_(options) {}

    Status open();

    std::string description() const override { return "TUM RGB-D sequence " + dir_.filename().string(); }
    Capabilities capabilities() const override {
        return {.sceneDepth = true,
                .smoothedSceneDepth = false,
                .confidence = false,
                .color = true,
                .pose = !groundTruth_.empty(),
                .nominalFps = recordedFps()};
    }
    std::size_t frameCount() const override { return pairs_.size(); }
    std::int64_t timestampNs(std::size_t i) const override {
        return secondsToNs(depth_[pairs_[i].first].timestampSeconds);
    }
    Expected<frame::Frame> frame(std::size_t i) override;
    std::vector<std::string> warnings() const override { return warnings_; }
    void setDecodeColor(bool decode) override { decodeColor_ = decode; }

private:
    Expected<std::vector<TumListEntry>> readList(const char* name);
    std::string resolve(const std::string& file) const {
        return fs::path(file).is_absolute() ? file : (dir_ / file).string();
    }
    std::optional<frame::Pose> poseAt(double seconds) const;

    fs::path dir_;
    TumOptions options_;
    std::vector<TumListEntry> rgb_, depth_;
    std::vector<TumPose> groundTruth_;
    std::vector<std::pair<std::size_t, std::size_t>> pairs_; // (depth, rgb)
    frame::Intrinsics intrinsics_ = kDefaultIntrinsics;
    std::vector<std::string> warnings_;
    bool decodeColor_ = true;
};

Expected<std::vector<TumListEntry>> TumSource::readList(const char* name) {
    const std::string file = (dir_ / name).string();
    auto text = readTextFile(file);
    if (!text)
        return Error{file + " is missing or unreadable (a TUM RGB-D sequence has rgb.txt and depth.txt)"};
    return parseTumList(*text, file);
}

Status TumSource::open() {
    auto rgb = readList("rgb.txt");
    if (!rgb)
        return rgb.error();
    auto depth = readList("depth.txt");
    if (!depth)
        return depth.error();
    rgb_ = std::move(*rgb);
    depth_ = std::move(*depth);
    std::vector<double> depthTimes, rgbTimes;
    for (const auto& e : depth_)
        depthTimes.push_back(e.timestampSeconds);
    for (const auto& e : rgb_)
        rgbTimes.push_back(e.timestampSeconds);
    pairs_ = associateByTimestamp(depthTimes, rgbTimes, options_.maxTimeDifferenceSeconds);
    if (pairs_.size() < depth_.size())
        warnings_.push_back(dir_.string() + ": " + std::to_string(depth_.size() - pairs_.size()) + " of " +
                            std::to_string(depth_.size()) + " depth images have no RGB image within " +
                            std::to_string(options_.maxTimeDifferenceSeconds) + " s and are left out");
    if (pairs_.empty())
        return {}; // reported as a zero-frame capture by openReplaySource
    const std::string groundTruthFile = (dir_ / "groundtruth.txt").string();
    if (std::error_code ec; fs::exists(groundTruthFile, ec)) {
        auto text = readTextFile(groundTruthFile);
        if (!text)
            return text.error();
        auto poses = parseTumGroundTruth(*text, groundTruthFile);
        if (!poses)
            return poses.error();
        groundTruth_ = std::move(*poses);
    }
    auto first = readColorImage(resolve(rgb_[pairs_.front().second].file));
    if (!first)
        return first.error();
    // The defaults describe the 640x480 Kinect image; a resized sequence gets them scaled.
    intrinsics_ = kDefaultIntrinsics.scaledTo(first->width, first->height);
    return {};
}

std::optional<frame::Pose> TumSource::poseAt(double seconds) const {
    if (groundTruth_.empty())
        return std::nullopt;
    const auto later = std::lower_bound(groundTruth_.begin(), groundTruth_.end(), seconds,
                                        [](const TumPose& p, double t) { return p.timestampSeconds < t; });
    auto best = later == groundTruth_.end() ? later - 1 : later;
    if (later != groundTruth_.begin() &&
        std::abs((later - 1)->timestampSeconds - seconds) < std::abs(best->timestampSeconds - seconds))
        best = later - 1;
    if (std::abs(best->timestampSeconds - seconds) > options_.maxTimeDifferenceSeconds)
        return std::nullopt;
    return best->pose;
}

Expected<frame::Frame> TumSource::frame(std::size_t i) {
    const TumListEntry& d = depth_[pairs_[i].first];
    const TumListEntry& c = rgb_[pairs_[i].second];
    frame::Frame frame;
    frame.sequence = i;
    frame.timestampNs = timestampNs(i);
    frame.cameraIntrinsics = intrinsics_;
    frame.pose = poseAt(d.timestampSeconds);
    auto depth = readDepthPng(resolve(d.file), kMetersPerUnit);
    if (!depth)
        return Error{"frame " + std::to_string(i) + ": " + depth.error().message};
    frame.sceneDepth = frame::DepthData{std::move(*depth), {}};
    if (decodeColor_) {
        auto image = readColorImage(resolve(c.file));
        if (!image)
            return Error{"frame " + std::to_string(i) + ": " + image.error().message};
        frame.capturedImage = std::move(*image);
    }
    return frame;
}

} // namespace

Expected<std::unique_ptr<ReplaySource>> openTumSource(const std::string& directory, TumOptions options) {
    fs::path dir(directory);
    if (!dir.has_filename())
        dir = dir.parent_path();
    auto source = std::make_unique<TumSource>(dir, options);
    if (Status s = source->open(); !s)
        return s.error();
    return std::unique_ptr<ReplaySource>(std::move(source));
}

} // namespace dc::devices::replay
