#include "devices/replay/replay_source.h"

#include "devices/log.h"
#include "devices/replay/importers.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <filesystem>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Every replayed sample passes through here, so it runs 4 samples per step on SSE2 (every x86-64 has it;
// GCC's -O2 leaves the scalar loop unvectorised). Comparisons instead of isfinite: NaN fails both.
std::size_t sanitizeDepth(Plane<float>& depthMeters) {
    constexpr float kLargest = std::numeric_limits<float>::max();
    float* v = depthMeters.pixels.data();
    const std::size_t n = depthMeters.pixels.size();
    std::size_t fixed = 0, i = 0;
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps(), largest = _mm_set1_ps(kLargest);
    const __m128i one = _mm_set1_epi32(1);
    __m128i invalid = _mm_setzero_si128(); // per lane: how many invalid samples it saw
    for (; i + 4 <= n; i += 4) {
        const __m128 x = _mm_loadu_ps(v + i);
        const __m128 valid = _mm_and_ps(_mm_cmpge_ps(x, zero), _mm_cmple_ps(x, largest));
        invalid = _mm_add_epi32(invalid, _mm_andnot_si128(_mm_castps_si128(valid), one));
        _mm_storeu_ps(v + i, _mm_and_ps(x, valid));
    }
    alignas(16) std::uint32_t lanes[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes), invalid);
    fixed = std::size_t{lanes[0]} + lanes[1] + lanes[2] + lanes[3];
#endif
    for (; i < n; ++i) {
        const bool valid = v[i] >= 0.0f && v[i] <= kLargest;
        fixed += valid ? 0 : 1;
        v[i] = valid ? v[i] : 0.0f;
    }
    return fixed;
}

namespace {

std::size_t sanitize(std::optional<DepthData>& depth) {
    if (!depth)
        return 0;
    if (!depth->confidence.empty()) {
        cv::Mat confidence(1, static_cast<int>(depth->confidence.pixels.size()), CV_8U,
                           depth->confidence.pixels.data());
        cv::min(confidence, static_cast<int>(Confidence::High), confidence); // vectorised, unlike a loop
    }
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

} // namespace

Expected<Frame> loadFrame(ReplaySource& source, std::size_t i) {
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

Pose poseFromQuaternion(const double t[3], const double q[4]) {
    double x = q[0], y = q[1], z = q[2], w = q[3];
    const double norm = std::sqrt(x * x + y * y + z * z + w * w);
    if (norm > 0.0) {
        x /= norm, y /= norm, z /= norm, w /= norm;
    }
    // Row-major rotation from the unit quaternion, stored column-major below.
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    Pose pose;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            pose.cameraToWorld[col * 4 + row] = r[row][col];
    for (int row = 0; row < 3; ++row)
        pose.cameraToWorld[12 + row] = t[row];
    return pose;
}

Expected<std::unique_ptr<ReplaySource>> openReplaySource(const std::string& path,
                                                         const ReplayOpenOptions& options) {
    const std::filesystem::path p(path);
    Expected<std::unique_ptr<ReplaySource>> source = Error{""};
    if (!pathExists(p))
        return Error{path + " does not exist"};
    if (!isDirectory(p))
        source = openRecordingSource(path);
    else if (pathExists(p / "rgb.txt") || pathExists(p / "depth.txt"))
        source = openTumSource(path);
    else if (isDirectory(p / "depth"))
        source = openStraySource(path);
    else
        return Error{path +
                     ": not a recording, a Stray Scanner directory (depth/, rgb.mp4, camera_matrix.csv, "
                     "odometry.csv) or a TUM RGB-D directory (rgb.txt, depth.txt)"};
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
