#include "processing/fog.h"

#include "processing/parallel.h"
#include "processing/pipeline.h"
#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dc::processing {

namespace {

constexpr int kMaxBlurWidth = 320;

// Fog amount in [0, 1] at the depth map's resolution: depth / fogMax, clamped, then blurred. A pixel
// without a measurement is beyond the sensor's range (the window in the desk scene, the sky outdoors), so
// its amount is 1, never the 0 that its stored depth of 0 m would give.
cv::Mat fogAmount(const frame::Plane<float>& depth, const FogSettings& settings) {
    const float fogMax = std::max(settings.fogMaxMeters, 1e-6f);
    cv::Mat amount(depth.height, depth.width, CV_32F);
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const float d = depth.at(x, y);
            amount.at<float>(y, x) = std::isfinite(d) && d > 0.0f ? std::min(d / fogMax, 1.0f) : 1.0f;
        }
    // The blur smooths over many pixels: on a map upsampled to the camera's size it runs on a copy at most
    // kMaxBlurWidth wide, with sigma scaled alike (the same blur in the image, several times cheaper).
    const int shrink = (depth.width + kMaxBlurWidth - 1) / kMaxBlurWidth;
    if (shrink > 1)
        amount = resized(amount, {std::max(1, depth.width / shrink), std::max(1, depth.height / shrink)});
    if (settings.blurSigmaPixels > 0.0f)
        cv::GaussianBlur(amount, amount, cv::Size(), settings.blurSigmaPixels / static_cast<float>(shrink));
    return amount;
}

// The weight of the fogged color against the debug red per depth pixel: confidence / 2, at most 1; empty
// (everywhere 1) without overlay or without a confidence map.
std::vector<float> keptWeight(const frame::DepthData& depth, bool overlay) {
    if (!overlay || depth.confidence.empty() ||
        depth.confidence.pixels.size() != depth.depthMeters.pixels.size())
        return {};
    std::vector<float> keep(depth.confidence.pixels.size());
    for (std::size_t i = 0; i < keep.size(); ++i)
        keep[i] = std::min(depth.confidence.pixels[i], std::uint8_t{2}) * 0.5f;
    return keep;
}

} // namespace

RgbaImage renderFog(const frame::Frame& frame, const FogSettings& settings, DepthSource source) {
    const auto [width, height] = halfCameraSize(frame.capturedImage);
    return renderFog(cameraRgbImage(frame.capturedImage, width, height), shownDepth(frame, source), settings);
}

RgbaImage renderFog(const RgbImage& cameraImage, const frame::DepthData* depth, const FogSettings& settings) {
    if (cameraImage.empty())
        return {};
    const int width = cameraImage.width, height = cameraImage.height;
    const std::vector<std::uint8_t>& rgb = cameraImage.pixels;
    const frame::DepthData none{frame::Plane<float>(1, 1), {}};
    const bool fogged = depth && !depth->depthMeters.empty();
    const frame::DepthData& d = fogged ? *depth : none;
    // No depth map: an amount of 0 everywhere, the plain camera image.
    const cv::Mat amount =
        fogged ? fogAmount(d.depthMeters, settings) : cv::Mat(1, 1, CV_32F, cv::Scalar(0.0f));
    const RowSampler amountAt(amount, width, height);
    const std::vector<float> keep = keptWeight(d, settings.confidenceOverlay);
    const std::array<float, 3> fog{settings.color[0] * 255.0f, settings.color[1] * 255.0f,
                                   settings.color[2] * 255.0f};
    const std::array<float, 3> red{255.0f, 0.0f, 0.0f};
    const std::array<cv::Mat, 3> camera = rgbPlanes(rgb, width, height);
    RgbaImage out{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    parallelRanges(height, 32, [&](int begin, int end) {
        std::vector<float> a(static_cast<std::size_t>(width)), toRed(a.size()), scratch;
        std::array<std::vector<std::uint8_t>, 3> fogged, tinted;
        for (int c = 0; c < 3; ++c)
            fogged[c].resize(a.size()), tinted[c].resize(a.size());
        for (int y = begin; y < end; ++y) {
            amountAt.sample(y, a.data(), scratch);
            const int dy = y * d.depthMeters.height / height; // nearest, as the sample's uint texture
            for (int x = 0; !keep.empty() && x < width; ++x)
                toRed[x] = 1.0f - keep[static_cast<std::size_t>(dy) * d.depthMeters.width +
                                       x * d.depthMeters.width / width];
            for (int c = 0; c < 3; ++c) {
                mixRow(camera[c].ptr<std::uint8_t>(y), fog[c], a.data(), fogged[c].data(), width);
                if (!keep.empty())
                    mixRow(fogged[c].data(), red[c], toRed.data(), tinted[c].data(), width);
            }
            const auto& final = keep.empty() ? fogged : tinted;
            mergeRgba(final[0].data(), final[1].data(), final[2].data(),
                      out.pixels.data() + static_cast<std::size_t>(y) * width * 4, width);
        }
    });
    return out;
}

} // namespace dc::processing
