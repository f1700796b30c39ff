#include "devices/replay/replay_source.h"

#include "base/log.h"
#include "devices/recording/format.h"
#include "devices/replay/importers.h"
#include "frame/camera_model.h"

#ifdef DC_HAVE_ROS
#include "devices/ros/bag_source.h"
#include "devices/ros/mcap_source.h"
#endif

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>

namespace dc::devices::replay {

std::size_t ReplaySource::indexAtTime(std::int64_t ns) const {
    std::size_t lo = 0, hi = frameCount();
    while (lo < hi) { // first frame after `ns`
        const std::size_t mid = lo + (hi - lo) / 2;
        if (timestampNs(mid) <= ns)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo == 0 ? 0 : lo - 1;
}

double ReplaySource::recordedFps() const {
    const std::size_t n = frameCount();
    if (n < 2 || timestampNs(n - 1) <= timestampNs(0))
        return 0.0;
    return static_cast<double>(n - 1) * 1e9 / static_cast<double>(timestampNs(n - 1) - timestampNs(0));
}

// Every replayed sample passes through here, so this file is built with -O3 (CMakeLists.txt) and the loop
// is written to vectorise: two comparisons instead of isfinite (NaN fails both), combined bitwise, and a
// select, not a branch.
std::size_t sanitizeDepth(frame::Plane<float>& depthMeters) {
    constexpr float kLargest = std::numeric_limits<float>::max();
    std::uint32_t fixed = 0; // 32-bit lanes vectorise better; no image has 2^32 samples
    for (float& v : depthMeters.pixels) {
        const int valid = (v >= 0.0f) & (v <= kLargest); // bitwise: no control flow
        fixed += static_cast<std::uint32_t>(valid ^ 1);
        v = valid ? v : 0.0f;
    }
    return fixed;
}

namespace {

std::size_t sanitize(std::optional<frame::DepthData>& depth) {
    if (!depth)
        return 0;
    for (std::uint8_t& c : depth->confidence.pixels)
        c = std::min<std::uint8_t>(c, static_cast<std::uint8_t>(frame::Confidence::High));
    return sanitizeDepth(depth->depthMeters);
}

bool isDirectory(const std::filesystem::path& p) {
    std::error_code ec;
    return std::filesystem::is_directory(p, ec);
}

bool pathExists(const std::filesystem::path& p) {
    std::error_code ec;
    return std::filesystem::exists(p, ec);
}

Expected<std::unique_ptr<ReplaySource>> openBag(const std::string& path, const ReplayOpenOptions& options) {
#ifdef DC_HAVE_ROS
    return ros::openBagSource(path, {.depthTopic = options.depthTopic, .colorTopic = options.colorTopic});
#else
    (void)options;
    return Error{path +
                 ": this depthcloud was built without ROS (-DDC_ROS=OFF), so it cannot read .bag files"};
#endif
}

Expected<std::unique_ptr<ReplaySource>> openMcap(const std::string& path, const ReplayOpenOptions& options) {
#ifdef DC_HAVE_ROS
    return ros::openMcapSource(path, {.depthTopic = options.depthTopic, .colorTopic = options.colorTopic});
#else
    (void)options;
    return Error{path + ": this depthcloud was built without ROS (-DDC_ROS=OFF), so it cannot read ROS 2 "
                        "recordings"};
#endif
}

} // namespace

Expected<frame::Frame> loadFrame(ReplaySource& source, std::size_t i) {
    auto frame = source.frame(i);
    if (!frame)
        return frame;
    const std::size_t fixed = sanitize(frame->sceneDepth) + sanitize(frame->smoothedSceneDepth);
    if (fixed > 0)
        logWarning(source.description() + ": frame " + std::to_string(i) + ": " + std::to_string(fixed) +
                   " NaN or negative depth samples set to 0 (no measurement)");
    return frame;
}

std::int64_t secondsToNs(double seconds) {
    return std::llround(seconds * 1e9);
}

frame::Pose poseFromQuaternion(const double t[3], const double q[4]) {
    double x = q[0], y = q[1], z = q[2], w = q[3];
    const double norm = std::sqrt(x * x + y * y + z * z + w * w);
    if (norm > 0.0) {
        x /= norm, y /= norm, z /= norm, w /= norm;
    }
    // Row-major rotation from the unit quaternion, stored column-major below.
    const std::array<double, 9> r = frame::rotationFromQuaternion({x, y, z, w});
    frame::Pose pose;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            pose.cameraToWorld[col * 4 + row] = r[row * 3 + col];
    for (int row = 0; row < 3; ++row)
        pose.cameraToWorld[12 + row] = t[row];
    return pose;
}

namespace {

constexpr std::string_view kMcapMagic{"\x89MCAP0\r\n", 8};
constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};

std::string lowercaseExtension(const std::filesystem::path& p) {
    std::string extension = p.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

CaptureKind classifyFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::array<char, 16> head{};
    in.read(head.data(), head.size());
    const std::string_view read(head.data(), static_cast<std::size_t>(in.gcount()));
    if (read.starts_with("#ROSBAG "))
        return CaptureKind::RosBag;
    if (read.starts_with(kMcapMagic))
        return CaptureKind::Mcap;
    if (read.starts_with(kSqliteMagic))
        return CaptureKind::Rosbag2;
    if (read.size() >= recording::kFileMagic.size() &&
        std::equal(recording::kFileMagic.begin(), recording::kFileMagic.end(), read.begin(),
                   [](std::uint8_t a, char b) { return a == static_cast<std::uint8_t>(b); }))
        return CaptureKind::DcRecording;
    // A file that only carries the name still goes to its reader, which says what is wrong with it.
    const std::string extension = lowercaseExtension(p);
    if (extension == ".bag")
        return CaptureKind::RosBag;
    if (extension == ".mcap")
        return CaptureKind::Mcap;
    if (extension == ".db3")
        return CaptureKind::Rosbag2;
    return extension == ".dcrec" ? CaptureKind::DcRecording : CaptureKind::OtherFile;
}

} // namespace

CaptureKind classifyCapture(const std::filesystem::path& path) {
    if (!pathExists(path))
        return CaptureKind::Missing;
    if (!isDirectory(path))
        return classifyFile(path);
    if (pathExists(path / "metadata.yaml"))
        return CaptureKind::Rosbag2;
    if (pathExists(path / "rgb.txt") || pathExists(path / "depth.txt"))
        return CaptureKind::TumSequence;
    return isDirectory(path / "depth") ? CaptureKind::StrayCapture : CaptureKind::Folder;
}

Expected<std::unique_ptr<ReplaySource>> openReplaySource(const std::string& path,
                                                         const ReplayOpenOptions& options) {
    Expected<std::unique_ptr<ReplaySource>> source = Error{""};
    switch (classifyCapture(path)) {
    case CaptureKind::Missing:
        return Error{path + " does not exist"};
    case CaptureKind::RosBag:
        source = openBag(path, options);
        break;
    case CaptureKind::Mcap:
    case CaptureKind::Rosbag2:
        source = openMcap(path, options);
        break;
    case CaptureKind::DcRecording:
    case CaptureKind::OtherFile: // the recording reader names what the file lacks
        source = openRecordingSource(path);
        break;
    case CaptureKind::TumSequence:
        source = openTumSource(path);
        break;
    case CaptureKind::StrayCapture:
        source = openStraySource(path);
        break;
    case CaptureKind::Folder:
        return Error{path +
                     ": not a recording, a Stray Scanner directory (depth/, rgb.mp4, camera_matrix.csv, "
                     "odometry.csv) or a TUM RGB-D directory (rgb.txt, depth.txt)"};
    }
    if (!source)
        return source;
    if ((*source)->frameCount() == 0)
        return Error{path + " holds no frames (zero-frame recording)"};
    for (const std::string& w : (*source)->warnings())
        logWarning(w);
    if (!options.calibrationPath.empty())
        return withCalibration(std::move(*source), options.calibrationPath);
    return source;
}

} // namespace dc::devices::replay
