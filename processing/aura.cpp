#include "processing/aura.h"

#include "processing/parallel.h"
#include "processing/pipeline.h"
#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <vector>

namespace dc::processing {

namespace {

// The LiDAR's own width: finer mattes add nothing, as the ring is made at 240 pixels wide (kWorkScale).
constexpr int kMaxMatteWidth = 256;
constexpr double kWorkScale = 0.25; // working resolution relative to the output image
constexpr double kPi = 3.14159265358979323846;
// A region nearer than this to the image's edge touches it: sensors smear their outermost pixels (ARKit's
// last column mixes the nearer and the farther surface).
constexpr int kBorderPixels = 2;
// Without intrinsics a pixel's physical size is guessed from a 60 degree horizontal field of view, about
// what depth cameras have (ARKit's LiDAR 64, RealSense D435 87, Kinect v1 57).
constexpr double kFallbackTanHalfFov = 0.57735026918962576;

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
        matte.pixels[i] = frame::isMeasured(d) && d >= s.nearMeters && d <= s.farMeters;
    }
}

// A connected set of pixels nearer than some depth, followed from its nearest pixel (its birth) to the depth
// at which it first touches a set that began nearer (its death): 0-dimensional persistence of the depth
// map's sublevel sets.
struct Basin {
    float birthMeters = 0.0f;
    float deathMeters = std::numeric_limits<float>::infinity();
    int seed = 0; // the nearest pixel
};

// The measured pixels' indices, nearest first and ties by index: a least-significant-digit radix sort of the
// depths' bits, a byte a pass (a positive float's bits order as the float does). About 20 times faster than
// std::sort on a LiDAR map, whose millimetre depths repeat a lot; the sort was most of the matte's cost.
std::vector<int> nearestFirst(const frame::Plane<float>& depth) {
    std::vector<std::uint32_t> keys;
    std::vector<int> order;
    for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
        if (frame::isMeasured(depth.pixels[i])) {
            keys.push_back(std::bit_cast<std::uint32_t>(depth.pixels[i]));
            order.push_back(static_cast<int>(i));
        }
    }
    std::vector<std::uint32_t> sortedKeys(keys.size());
    std::vector<int> sortedOrder(order.size());
    for (int shift = 0; shift < 32; shift += 8) {
        std::array<std::size_t, 257> next{};
        for (std::uint32_t k : keys)
            ++next[((k >> shift) & 0xffu) + 1];
        std::partial_sum(next.begin(), next.end(), next.begin());
        for (std::size_t i = 0; i < keys.size(); ++i) {
            const std::size_t at = next[(keys[i] >> shift) & 0xffu]++;
            sortedKeys[at] = keys[i];
            sortedOrder[at] = order[i];
        }
        keys.swap(sortedKeys);
        order.swap(sortedOrder);
    }
    return order;
}

class BasinForest {
public:
    explicit BasinForest(const frame::Plane<float>& depth)
        : depth_(depth), parent_(depth.pixels.size(), -1) {}

    // Adds every measured pixel, nearest first, and returns every basin (those still alive at the end never
    // died). Each merge ends the basin that began farther.
    std::vector<Basin> grow() {
        const std::vector<int> order = nearestFirst(depth_);
        std::vector<Basin> basins;
        for (int i : order)
            add(i, basins);
        for (int i : order)
            if (parent_[i] == i)
                basins.push_back({depth_.pixels[i], std::numeric_limits<float>::infinity(), i});
        return basins;
    }

private:
    int root(int i) {
        while (parent_[i] != i)
            i = parent_[i] = parent_[parent_[i]];
        return i;
    }

    void add(int i, std::vector<Basin>& basins) {
        const float d = depth_.pixels[i];
        parent_[i] = i;
        const int x = i % depth_.width, y = i / depth_.width;
        const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& [nx, ny] : neighbours) {
            if (nx < 0 || ny < 0 || nx >= depth_.width || ny >= depth_.height)
                continue;
            const int n = ny * depth_.width + nx;
            if (parent_[n] < 0)
                continue;
            int a = root(i), b = root(n);
            if (a == b)
                continue;
            // A root is its basin's nearest pixel; ties go to the lower index, as the order above.
            if (depth_.pixels[b] < depth_.pixels[a] || (depth_.pixels[b] == depth_.pixels[a] && b < a))
                std::swap(a, b);
            if (b != i) // a basin of the pixel alone is no basin
                basins.push_back({depth_.pixels[b], d, b});
            parent_[b] = a;
        }
    }

    const frame::Plane<float>& depth_;
    std::vector<int> parent_; // -1 while the pixel is not yet added
};

// Area of one pixel at 1 m, in square meters.
double pixelAreaAtOneMeter(const frame::Intrinsics& k, int width, int height) {
    if (k.valid()) {
        const frame::Intrinsics s = k.scaledTo(width, height);
        return 1.0 / (s.fx * s.fy);
    }
    const double f = width / (2.0 * kFallbackTanHalfFov);
    return 1.0 / (f * f);
}

struct Region {
    bool touchesBorder = false;
    double areaSquareMeters = 0.0;
};

// Marks the pixels connected to `seed` through measured depths below `limitMeters`.
Region fill(const frame::Plane<float>& depth, int seed, float limitMeters, double pixelAreaAtOneMeter,
            frame::Plane<std::uint8_t>& matte) {
    Region region;
    std::vector<int> stack{seed};
    matte.pixels[seed] = 1;
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int x = i % depth.width, y = i / depth.width;
        region.touchesBorder |= std::min({x, y, depth.width - 1 - x, depth.height - 1 - y}) < kBorderPixels;
        region.areaSquareMeters += pixelAreaAtOneMeter * depth.pixels[i] * depth.pixels[i];
        const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& [nx, ny] : neighbours) {
            if (nx < 0 || ny < 0 || nx >= depth.width || ny >= depth.height)
                continue;
            const int n = ny * depth.width + nx;
            const float d = depth.pixels[n];
            if (matte.pixels[n] || !frame::isMeasured(d) || d >= limitMeters)
                continue;
            matte.pixels[n] = 1;
            stack.push_back(n);
        }
    }
    return region;
}

// The nearest basin that stands out (see AuraSettings), filled into `matte`; nothing when none does.
void fillNearestSubject(const frame::Plane<float>& depth, const frame::Intrinsics& intrinsics,
                        const AuraSettings& s, frame::Plane<std::uint8_t>& matte) {
    std::vector<Basin> basins = BasinForest(depth).grow();
    std::erase_if(basins, [&](const Basin& b) { return b.deathMeters - b.birthMeters < s.separationMeters; });
    std::sort(basins.begin(), basins.end(),
              [](const Basin& a, const Basin& b) { return a.birthMeters < b.birthMeters; });
    const double pixelArea = pixelAreaAtOneMeter(intrinsics, depth.width, depth.height);
    for (const Basin& b : basins) {
        // The basin holds all of its nearest separationMeters: it lives longer.
        frame::Plane<std::uint8_t> cap(depth.width, depth.height);
        const Region front = fill(depth, b.seed, b.birthMeters + s.separationMeters, pixelArea, cap);
        if (front.touchesBorder ||
            front.areaSquareMeters < static_cast<double>(s.minSizeMeters) * s.minSizeMeters)
            continue;
        fill(depth, b.seed, std::min(b.deathMeters, b.birthMeters + s.regionDepthMeters), pixelArea, matte);
        return;
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

frame::Plane<std::uint8_t> subjectMatte(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                        const AuraSettings& settings) {
    const frame::Plane<float> d = matteDepth(depth.depthMeters);
    frame::Plane<std::uint8_t> matte(d.width, d.height);
    if (settings.matte == AuraMatte::NearRange)
        nearRange(d, settings, matte);
    else
        fillNearestSubject(d, intrinsics, settings, matte);
    return matte;
}

RgbaImage renderAura(const frame::Frame& frame, const AuraSettings& settings, DepthSource source,
                     double timeSeconds) {
    const auto [width, height] = halfCameraSize(frame.capturedImage);
    return renderAura(cameraRgbImage(frame.capturedImage, width, height), shownDepth(frame, source),
                      frame.depthIntrinsics(), settings, timeSeconds);
}

RgbaImage renderAura(const RgbImage& cameraImage, const frame::DepthData* depth,
                     const frame::Intrinsics& depthIntrinsics, const AuraSettings& settings,
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
        cv::resize(asMat(subjectMatte(*depth, depthIntrinsics, settings)), matte, work, 0, 0,
                   cv::INTER_NEAREST);
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
