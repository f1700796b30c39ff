#include "devices/replay/capture_files.h"
#include "devices/replay/importers.h"
#include "devices/replay/stray_format.h"
#include "devices/video/video_codec.h"
#include "frame/rgb_image.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>

namespace dc::devices::replay {

namespace {

namespace fs = std::filesystem;

constexpr double kMetersPerMillimeter = 0.001;
// Reading ahead this many frames is cheaper than a seek, which restarts decoding at a key frame.
constexpr std::size_t kMaxReadAhead = 30;

std::string frameName(std::size_t i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    return name;
}

// The frame numbers of a depth/ or confidence/ folder: NNNNNN.png, numbered from 0 without gaps.
Expected<std::size_t> countNumberedPngs(const fs::path& dir) {
    std::vector<std::size_t> numbers;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        std::size_t n = 0;
        const auto [ptr, err] = std::from_chars(name.data(), name.data() + name.size(), n);
        if (err == std::errc() && std::string_view(ptr) == ".png")
            numbers.push_back(n);
    }
    if (ec)
        return Error{"cannot list " + dir.string() + ": " + ec.message()};
    std::sort(numbers.begin(), numbers.end());
    for (std::size_t i = 0; i < numbers.size(); ++i)
        if (numbers[i] != i)
            return Error{(dir / frameName(i)).string() + " is missing (" + dir.filename().string() +
                         "/ has " + std::to_string(numbers.size()) + " numbered PNGs up to " +
                         frameName(numbers.back()) + ")"};
    return numbers.size();
}

class StraySource final : public ReplaySource {
public:
    explicit StraySource(fs::path dir) : dir_(std::move(dir)) {}

    Status open();

    std::string description() const override { return "Stray Scanner capture " + dir_.filename().string(); }
    Capabilities capabilities() const override {
        return {.sceneDepth = true,
                .smoothedSceneDepth = false,
                .confidence = hasConfidence_,
                .color = true,
                .pose = true,
                .nominalFps = recordedFps()};
    }
    std::size_t frameCount() const override { return frames_; }
    std::int64_t timestampNs(std::size_t i) const override {
        return secondsToNs(odometry_[i].timestampSeconds);
    }
    Expected<frame::Frame> frame(std::size_t i) override;
    std::vector<std::string> warnings() const override { return warnings_; }
    void setDecodeColor(bool decode) override { decodeColor_ = decode; }

private:
    Status openVideo();
    Expected<frame::CapturedImage> videoFrame(std::size_t i);

    fs::path dir_;
    std::size_t frames_ = 0;
    bool hasConfidence_ = false;
    bool decodeColor_ = true;
    frame::Intrinsics intrinsics_;
    std::vector<StrayOdometryRow> odometry_;
    std::vector<std::string> warnings_;
    std::unique_ptr<video::VideoReader> video_;
    std::size_t nextVideoFrame_ = 0;
};

Status StraySource::open() {
    auto depthFrames = countNumberedPngs(dir_ / "depth");
    if (!depthFrames)
        return depthFrames.error();
    frames_ = *depthFrames;
    if (frames_ == 0)
        return Error{(dir_ / "depth").string() + " holds no frames (zero-frame capture)"};
    std::error_code ec;
    hasConfidence_ = fs::is_directory(dir_ / "confidence", ec);
    if (hasConfidence_) {
        auto confidenceFrames = countNumberedPngs(dir_ / "confidence");
        if (!confidenceFrames)
            return confidenceFrames.error();
        if (*confidenceFrames != frames_)
            return Error{dir_.string() + ": mismatched frame counts: depth/ has " + std::to_string(frames_) +
                         " frames, confidence/ has " + std::to_string(*confidenceFrames)};
    } else {
        warnings_.push_back(dir_.string() + ": no confidence/ folder: the capture has no confidence");
    }
    for (const char* required : {"camera_matrix.csv", "odometry.csv", "rgb.mp4"})
        if (!fs::exists(dir_ / required, ec))
            return Error{(dir_ / required).string() + " is missing (a Stray Scanner capture has depth/, "
                                                      "camera_matrix.csv, odometry.csv and rgb.mp4)"};
    const std::string matrixFile = (dir_ / "camera_matrix.csv").string();
    auto text = readTextFile(matrixFile);
    if (!text)
        return text.error();
    auto k = parseStrayCameraMatrix(*text, matrixFile);
    if (!k)
        return k.error();
    intrinsics_ = *k;
    const std::string odometryFile = (dir_ / "odometry.csv").string();
    if (text = readTextFile(odometryFile); !text)
        return text.error();
    auto rows = parseStrayOdometry(*text, odometryFile);
    if (!rows)
        return rows.error();
    if (rows->size() != frames_)
        return Error{dir_.string() + ": mismatched frame counts: depth/ has " + std::to_string(frames_) +
                     " frames, odometry.csv has " + std::to_string(rows->size()) + " rows"};
    odometry_ = std::move(*rows);
    return openVideo();
}

Status StraySource::openVideo() {
    const std::string file = (dir_ / "rgb.mp4").string();
    if (Status s = video::loadVideoSupport(); !s)
        return s;
    auto reader = video::openVideoReader(file);
    cv::Mat first;
    if (!reader || !(*reader)->read(first))
        return Error{"cannot decode " + file + " (unreadable video)"};
    video_ = std::move(*reader);
    nextVideoFrame_ = 1;
    const long long videoFrames = video_->frameCount();
    if (videoFrames != static_cast<long long>(frames_))
        return Error{dir_.string() + ": mismatched frame counts: depth/ has " + std::to_string(frames_) +
                     " frames, rgb.mp4 has " + std::to_string(videoFrames)};
    intrinsics_.width = first.cols;
    intrinsics_.height = first.rows;
    return {};
}

Expected<frame::CapturedImage> StraySource::videoFrame(std::size_t i) {
    const std::string file = (dir_ / "rgb.mp4").string();
    if (i < nextVideoFrame_ || i - nextVideoFrame_ > kMaxReadAhead) {
        video_->seek(i);
        nextVideoFrame_ = i;
    }
    while (nextVideoFrame_ < i) {
        if (!video_->grab())
            return Error{file + ": frame " + std::to_string(nextVideoFrame_) + " cannot be decoded"};
        ++nextVideoFrame_;
    }
    cv::Mat bgr;
    if (!video_->read(bgr)) {
        nextVideoFrame_ = frames_ + kMaxReadAhead + 1; // force a seek next time
        return Error{file + ": frame " + std::to_string(i) + " cannot be decoded"};
    }
    ++nextVideoFrame_;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(bgr.cols) * bgr.rows * 3);
    cv::cvtColor(bgr, cv::Mat(bgr.rows, bgr.cols, CV_8UC3, rgb.data()), cv::COLOR_BGR2RGB);
    return frame::makeRgb24Image(bgr.cols, bgr.rows, std::move(rgb));
}

Expected<frame::Frame> StraySource::frame(std::size_t i) {
    frame::Frame frame;
    frame.sequence = i;
    frame.timestampNs = timestampNs(i);
    frame.pose = odometry_[i].pose;
    frame.cameraIntrinsics = intrinsics_;
    auto depth = readDepthPng((dir_ / "depth" / frameName(i)).string(), kMetersPerMillimeter);
    if (!depth)
        return Error{"frame " + std::to_string(i) + ": " + depth.error().message};
    frame::DepthData data{std::move(*depth), {}};
    if (hasConfidence_) {
        const std::string file = (dir_ / "confidence" / frameName(i)).string();
        auto confidence = readConfidencePng(file);
        if (!confidence)
            return Error{"frame " + std::to_string(i) + ": " + confidence.error().message};
        if (confidence->width != data.depthMeters.width || confidence->height != data.depthMeters.height)
            return Error{"frame " + std::to_string(i) + ": " + file + " is not the size of its depth map"};
        data.confidence = std::move(*confidence);
    }
    frame.sceneDepth = std::move(data);
    if (decodeColor_) {
        auto image = videoFrame(i);
        if (!image)
            return image.error();
        frame.capturedImage = std::move(*image);
    }
    return frame;
}

} // namespace

Expected<std::unique_ptr<ReplaySource>> openStraySource(const std::string& directory) {
    fs::path dir(directory);
    if (!dir.has_filename())
        dir = dir.parent_path(); // "capture/" names the same directory as "capture"
    auto source = std::make_unique<StraySource>(dir);
    if (Status s = source->open(); !s)
        return s.error();
    return std::unique_ptr<ReplaySource>(std::move(source));
}

} // namespace dc::devices::replay
