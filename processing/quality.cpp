#include "processing/quality.h"

#include "processing/resample.h"
#include "processing/temporal_smoothing.h"

#include <algorithm>
#include <cmath>

namespace dc::processing {

DepthError depthError(const frame::Plane<float>& estimate, const frame::Plane<float>& truth,
                      const frame::Plane<std::uint8_t>* mask) {
    DepthError e;
    if (estimate.pixels.size() != truth.pixels.size())
        return e;
    double absolute = 0.0, squared = 0.0;
    for (std::size_t i = 0; i < truth.pixels.size(); ++i) {
        if (mask && !mask->pixels[i])
            continue;
        const float q = estimate.pixels[i];
        const double diff = (std::isfinite(q) ? q : 0.0) - truth.pixels[i];
        absolute += std::abs(diff);
        squared += diff * diff;
        ++e.count;
    }
    if (e.count > 0) {
        e.mad = absolute / static_cast<double>(e.count);
        e.rmse = std::sqrt(squared / static_cast<double>(e.count));
    }
    return e;
}

frame::Plane<std::uint8_t> measuredFootprint(const frame::Plane<float>& low, int width, int height) {
    frame::Plane<std::uint8_t> mask(width, height);
    const BilinearTaps tx = bilinearTaps(low.width, width), ty = bilinearTaps(low.height, height);
    const auto ok = [&](int x, int y) {
        const float d = low.at(x, y);
        return std::isfinite(d) && d > 0.0f;
    };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            mask.at(x, y) = ok(tx.first[x], ty.first[y]) && ok(tx.second[x], ty.first[y]) &&
                            ok(tx.first[x], ty.second[y]) && ok(tx.second[x], ty.second[y]);
    return mask;
}

namespace {

constexpr auto kMedium = static_cast<std::uint8_t>(frame::Confidence::Medium);

std::vector<std::size_t> steadyPixels(const std::vector<frame::DepthData>& frames) {
    std::vector<std::size_t> pixels;
    const std::size_t n = frames.front().depthMeters.pixels.size();
    for (std::size_t i = 0; i < n; ++i) {
        const bool steady = std::all_of(frames.begin(), frames.end(), [&](const frame::DepthData& f) {
            const bool confident = f.confidence.empty() || f.confidence.pixels[i] >= kMedium;
            return f.depthMeters.pixels[i] > 0.0f && confident;
        });
        if (steady)
            pixels.push_back(i);
    }
    return pixels;
}

// Flicker and spread of `series[t][pixel]` over the frames [first, end).
void noiseOf(const std::vector<std::vector<float>>& series, std::size_t first, double& flicker,
             double& spread) {
    double flickerSum = 0.0, spreadSum = 0.0;
    std::size_t flickerCount = 0;
    const std::size_t pixels = series.front().size(), frames = series.size() - first;
    for (std::size_t p = 0; p < pixels; ++p) {
        double mean = 0.0;
        for (std::size_t t = first; t < series.size(); ++t)
            mean += series[t][p] / static_cast<double>(frames);
        double variance = 0.0;
        for (std::size_t t = first; t < series.size(); ++t) {
            variance += (series[t][p] - mean) * (series[t][p] - mean) / static_cast<double>(frames);
            if (t > first) {
                const double d = series[t][p] - series[t - 1][p];
                flickerSum += d * d;
                ++flickerCount;
            }
        }
        spreadSum += variance;
    }
    flicker = std::sqrt(flickerSum / static_cast<double>(std::max<std::size_t>(flickerCount, 1)));
    spread = std::sqrt(spreadSum / static_cast<double>(std::max<std::size_t>(pixels, 1)));
}

} // namespace

TemporalNoise measureTemporalNoise(const std::vector<frame::DepthData>& frames, const SmoothingParams& params,
                                   int warmupFrames) {
    TemporalNoise noise;
    const auto first = static_cast<std::size_t>(std::max(warmupFrames, 0));
    if (frames.size() < first + 3)
        return noise;
    const std::vector<std::size_t> pixels = steadyPixels(frames);
    noise.pixels = pixels.size();
    if (pixels.empty())
        return noise;
    TemporalSmoother smoother;
    std::vector<std::vector<float>> raw, smoothed;
    for (const frame::DepthData& f : frames) {
        const frame::DepthData s = smoother.smooth(f, params);
        raw.emplace_back();
        smoothed.emplace_back();
        for (std::size_t i : pixels) {
            raw.back().push_back(f.depthMeters.pixels[i]);
            smoothed.back().push_back(s.depthMeters.pixels[i]);
        }
    }
    noiseOf(raw, first, noise.rawFlicker, noise.rawSpread);
    noiseOf(smoothed, first, noise.smoothedFlicker, noise.smoothedSpread);
    return noise;
}

int measureStepLag(float stepMeters, const SmoothingParams& params) {
    constexpr int kWidth = 48, kHeight = 4, kStart = 8;
    constexpr float kBackground = 2.0f;
    const float middle = kBackground - stepMeters / 2.0f;
    TemporalSmoother smoother;
    std::vector<int> crossed(kWidth, -1); // frame at which each pixel's smoothed value passed the middle
    for (int frame = 0; frame < kWidth; ++frame) {
        frame::DepthData d{frame::Plane<float>(kWidth, kHeight, kBackground), {}};
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < std::min(kStart + frame, kWidth); ++x)
                d.depthMeters.at(x, y) = kBackground - stepMeters;
        const frame::DepthData s = smoother.smooth(d, params);
        for (int x = 0; x < kWidth; ++x)
            if (crossed[x] < 0 && s.depthMeters.at(x, kHeight / 2) < middle)
                crossed[x] = frame;
    }
    int lag = 0;
    for (int x = kStart; x < kWidth; ++x) {
        const int stepArrives = x - kStart + 1; // the first frame in which pixel x shows the foreground
        lag = std::max(lag, crossed[x] < 0 ? kWidth : crossed[x] - stepArrives);
    }
    return lag;
}

} // namespace dc::processing
