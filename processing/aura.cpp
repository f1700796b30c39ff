#include "processing/aura.h"

#include "processing/parallel.h"
#include "processing/pipeline.h"
#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dc::processing {

namespace {

constexpr int kMaxMatteWidth = 480;
constexpr double kWorkScale = 0.25; // working resolution relative to the output image
constexpr double kPi = 3.14159265358979323846;

bool measured(float d) {
    return std::isfinite(d) && d > 0.0f;
}

frame::Plane<float> matteDepth(const frame::Plane<float>& depth) {
    if (depth.width <= kMaxMatteWidth)
        return depth;
    const int w = kMaxMatteWidth, h = std::max(1, depth.height * kMaxMatteWidth / depth.width);
    frame::Plane<float> small(w, h);
    cv::resize(asMat(depth), asMat(small), {w, h}, 0, 0, cv::INTER_NEAREST);
    return small;
}

void nearRange(const frame::Plane<float>& depth, const AuraSettings& s, frame::Plane<std::uint8_t>& matte) {
    for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
        const float d = depth.pixels[i];
        matte.pixels[i] = measured(d) && d >= s.nearMeters && d <= s.farMeters;
    }
}

void nearestRegion(const frame::Plane<float>& depth, const AuraSettings& s,
                   frame::Plane<std::uint8_t>& matte) {
    std::vector<float> valid;
    for (float d : depth.pixels)
        if (measured(d))
            valid.push_back(d);
    if (valid.empty())
        return;
    const auto percentile = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 100);
    std::nth_element(valid.begin(), percentile, valid.end());
    const float start = *percentile, limit = start + s.regionDepthMeters;
    const auto seed = std::find(depth.pixels.begin(), depth.pixels.end(), start) - depth.pixels.begin();
    std::vector<int> stack{static_cast<int>(seed)};
    matte.pixels[seed] = 1;
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int x = i % depth.width, y = i / depth.width;
        const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& [nx, ny] : neighbours) {
            if (nx < 0 || ny < 0 || nx >= depth.width || ny >= depth.height)
                continue;
            const int n = ny * depth.width + nx;
            const float d = depth.pixels[n];
            if (matte.pixels[n] || !measured(d) || d > limit ||
                std::abs(d - depth.pixels[i]) > s.regionJumpMeters)
                continue;
            matte.pixels[n] = 1;
            stack.push_back(n);
        }
    }
}

// A normalised tent (triangle) blur `width` pixels wide, as MPSImageTent: two box blurs of half the width.
// Outside the image counts as 0, as MPS's default edge mode.
void tentBlur(cv::Mat& image, int width) {
    const int box = std::max(1, ((width + 1) / 2) | 1);
    for (int pass = 0; pass < 2; ++pass)
        cv::blur(image, image, {box, box}, cv::Point(-1, -1), cv::BORDER_CONSTANT);
}

// The article's blur sizes: odd, oscillating between base and 3 * base output pixels.
int pulsingWidth(double base, double phase) {
    return static_cast<int>((std::sin(phase) + 2.0) * base) | 1;
}

} // namespace

frame::Plane<std::uint8_t> subjectMatte(const frame::DepthData& depth, const AuraSettings& settings) {
    const frame::Plane<float> d = matteDepth(depth.depthMeters);
    frame::Plane<std::uint8_t> matte(d.width, d.height);
    if (settings.matte == AuraMatte::NearRange)
        nearRange(d, settings, matte);
    else
        nearestRegion(d, settings, matte);
    return matte;
}

RgbaImage renderAura(const frame::Frame& frame, const AuraSettings& settings, DepthSource source,
                     double timeSeconds) {
    const auto [width, height] = halfCameraSize(frame.capturedImage);
    return renderAura(cameraRgbImage(frame.capturedImage, width, height), shownDepth(frame, source), settings,
                      timeSeconds);
}

RgbaImage renderAura(const RgbImage& cameraImage, const frame::DepthData* depth, const AuraSettings& settings,
                     double timeSeconds) {
    if (cameraImage.empty())
        return {};
    const int width = cameraImage.width, height = cameraImage.height;
    const std::vector<std::uint8_t>& rgb = cameraImage.pixels;
    const cv::Size work(std::max(1, static_cast<int>(width * kWorkScale)),
                        std::max(1, static_cast<int>(height * kWorkScale)));
    cv::Mat white(work, CV_32F, cv::Scalar(0.0f));
    if (depth && !depth->depthMeters.empty()) {
        cv::Mat matte;
        cv::resize(asMat(subjectMatte(*depth, settings)), matte, work, 0, 0, cv::INTER_NEAREST);
        const int ring = std::max(1, static_cast<int>(std::lround(settings.ringPixels * kWorkScale)));
        cv::Mat dilated;
        cv::dilate(matte, dilated, cv::getStructuringElement(cv::MORPH_RECT, {ring, ring}));
        cv::Mat(dilated & ~matte).convertTo(white, CV_32F); // 0/1 images: 1 on the ring only
    }
    cv::Mat yellow = white.clone();
    const double phase = 2.0 * kPi * settings.pulseHz * timeSeconds;
    tentBlur(white, static_cast<int>(pulsingWidth(30.0, phase) * kWorkScale));
    tentBlur(yellow, static_cast<int>(pulsingWidth(100.0, phase) * kWorkScale));
    const RowSampler whiteAt(white, width, height), yellowAt(yellow, width, height);
    const std::array<cv::Mat, 3> camera = rgbPlanes(rgb, width, height);
    RgbaImage out{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    parallelRanges(height, 32, [&](int begin, int end) {
        std::vector<float> w(static_cast<std::size_t>(width)), yl(w.size()), warm(w.size()), scratch;
        std::array<std::vector<std::uint8_t>, 3> lit;
        for (auto& plane : lit)
            plane.resize(w.size());
        for (int y = begin; y < end; ++y) {
            whiteAt.sample(y, w.data(), scratch);
            yellowAt.sample(y, yl.data(), scratch);
            for (int x = 0; x < width; ++x) {
                w[x] *= 255.0f * settings.whiteGain;
                warm[x] = w[x] + 255.0f * settings.yellowGain * yl[x]; // white plus yellow (red + green)
            }
            addRow(camera[0].ptr<std::uint8_t>(y), warm.data(), lit[0].data(), width);
            addRow(camera[1].ptr<std::uint8_t>(y), warm.data(), lit[1].data(), width);
            addRow(camera[2].ptr<std::uint8_t>(y), w.data(), lit[2].data(), width);
            mergeRgba(lit[0].data(), lit[1].data(), lit[2].data(),
                      out.pixels.data() + static_cast<std::size_t>(y) * width * 4, width);
        }
    });
    return out;
}

} // namespace dc::processing
