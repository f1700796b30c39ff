#include "processing/fog.h"

#include "processing/parallel.h"
#include "processing/pipeline.h"
#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dc::processing {

namespace {

// Fog amount in [0, 1] at the depth map's resolution: depth / fogMax, clamped, then blurred. A pixel
// without a measurement is beyond the sensor's range (the window in the desk scene, the sky outdoors), so
// its amount is 1, never the 0 that its stored depth of 0 m would give.
cv::Mat fogAmount(const devices::Plane<float>& depth, const FogSettings& settings) {
    const float fogMax = std::max(settings.fogMaxMeters, 1e-6f);
    cv::Mat amount(depth.height, depth.width, CV_32F);
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const float d = depth.at(x, y);
            amount.at<float>(y, x) = std::isfinite(d) && d > 0.0f ? std::min(d / fogMax, 1.0f) : 1.0f;
        }
    if (settings.blurSigmaPixels > 0.0f)
        cv::GaussianBlur(amount, amount, cv::Size(), settings.blurSigmaPixels);
    return amount;
}

// Confidence at the output size, nearest-sampled as the sample's uint texture; empty when there is none.
cv::Mat confidenceAt(const devices::DepthData& depth, cv::Size size) {
    if (depth.confidence.pixels.size() != depth.depthMeters.pixels.size() || depth.confidence.empty())
        return {};
    cv::Mat out;
    cv::resize(asMat(depth.confidence), out, size, 0, 0, cv::INTER_NEAREST);
    return out;
}

float mix(float a, float b, float t) {
    return a + (b - a) * t;
}

} // namespace

RgbaImage renderFog(const devices::Frame& frame, const FogSettings& settings, DepthSource source) {
    const auto [width, height] = halfCameraSize(frame.capturedImage);
    const std::vector<std::uint8_t> rgb = cameraRgb(frame.capturedImage, width, height);
    if (rgb.empty())
        return {};
    RgbaImage out{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    const devices::DepthData* depth = shownDepth(frame, source);
    const bool fogged = depth && !depth->depthMeters.empty();
    const cv::Mat amount = fogged ? resized(fogAmount(depth->depthMeters, settings), {width, height})
                                  : cv::Mat(height, width, CV_32F, cv::Scalar(0.0f));
    const cv::Mat confidence =
        fogged && settings.confidenceOverlay ? confidenceAt(*depth, {width, height}) : cv::Mat();
    const std::array<float, 3> fogColor{settings.color[0] * 255.0f, settings.color[1] * 255.0f,
                                        settings.color[2] * 255.0f};
    const std::array<float, 3> red{255.0f, 0.0f, 0.0f};
    parallelRanges(height, 32, [&](int begin, int end) {
        for (int y = begin; y < end; ++y) {
            const float* a = amount.ptr<float>(y);
            const std::uint8_t* c = confidence.empty() ? nullptr : confidence.ptr<std::uint8_t>(y);
            for (int x = 0; x < width; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * width + x;
                const float keep =
                    settings.confidenceOverlay ? (c ? std::min(c[x], std::uint8_t{2}) : 2) / 2.0f : 1.0f;
                for (int k = 0; k < 3; ++k) {
                    const float fogged = mix(static_cast<float>(rgb[3 * i + k]), fogColor[k], a[x]);
                    out.pixels[4 * i + k] =
                        static_cast<std::uint8_t>(std::clamp(mix(red[k], fogged, keep), 0.0f, 255.0f) + 0.5f);
                }
                out.pixels[4 * i + 3] = 255;
            }
        }
    });
    return out;
}

} // namespace dc::processing
