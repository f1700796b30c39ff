#pragma once

// The dual-guided global smoother in double precision, written plainly (one pixel and one line at a time,
// the textbook tridiagonal elimination): the reference that the vectorised float implementation must match.

#include "processing/global_smoother.h"

#include <opencv2/imgproc.hpp>

#include "tests/unit/reference_depth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace dc::processing::reference {

struct Image {
    int width = 0, height = 0;
    std::vector<double> v;
    double& at(int x, int y) { return v[static_cast<std::size_t>(y) * width + x]; }
    double at(int x, int y) const { return v[static_cast<std::size_t>(y) * width + x]; }
};

inline Image image(int w, int h, double fill = 0.0) {
    return {w, h, std::vector<double>(static_cast<std::size_t>(w) * h, fill)};
}

// (I + L) x = r on a path with edge weights e[i] between i and i + 1, by textbook elimination: rows
// -e[i-1] x[i-1] + (1 + e[i-1] + e[i]) x[i] - e[i] x[i+1] = r[i].
inline void solveLine(std::vector<double>& r, const std::vector<double>& e) {
    const std::size_t n = r.size();
    std::vector<double> c(n), d(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = i > 0 ? -e[i - 1] : 0.0, upper = i + 1 < n ? -e[i] : 0.0;
        const double b = 1.0 - a - upper;
        const double m = i > 0 ? b - a * c[i - 1] : b;
        c[i] = upper / m;
        d[i] = (r[i] - (i > 0 ? a * d[i - 1] : 0.0)) / m;
    }
    for (std::size_t i = n; i-- > 0;)
        r[i] = d[i] - (i + 1 < n ? c[i] * r[i + 1] : 0.0);
}

struct Grid {
    Image dataSum, dataWeight, value, colorH, colorV;
};

inline Grid grid(int w, int h) {
    return {image(w, h), image(w, h), image(w, h), image(w, h), image(w, h)};
}

inline void colorDistances(ColorView g, Grid& out) {
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::uint8_t* p = g.pixels + y * g.stride + 3 * x;
            const std::uint8_t* right = g.pixels + y * g.stride + 3 * std::min(x + 1, g.width - 1);
            const std::uint8_t* below = g.pixels + std::min(y + 1, g.height - 1) * g.stride + 3 * x;
            double h = 0.0, v = 0.0;
            for (int c = 0; c < 3; ++c) {
                h += (right[c] - p[c]) * (right[c] - p[c]);
                v += (below[c] - p[c]) * (below[c] - p[c]);
            }
            out.colorH.at(x, y) = h;
            out.colorV.at(x, y) = v;
        }
}

inline double weight(double colorSquared, double dz, const SmootherPass& pass) {
    const double s = pass.colorSigma > 0.0f
                         ? colorSquared / (static_cast<double>(pass.colorSigma) * pass.colorSigma)
                         : 0.0;
    const double t = pass.depthSigma > 0.0f ? dz / pass.depthSigma : 0.0;
    return 1.0 / ((1.0 + std::pow(s, 4)) * (1.0 + t * t) * (1.0 + t * t));
}

inline void ratio(const Image& sum, const Image& w, Grid& g) {
    for (std::size_t i = 0; i < sum.v.size(); ++i) {
        const double own = g.dataWeight.v[i] > 0.0 ? g.dataSum.v[i] / g.dataWeight.v[i] : 0.0;
        g.value.v[i] = w.v[i] > 1e-6 ? sum.v[i] / w.v[i] : own;
    }
}

inline void runPass(Grid& g, const SmootherPass& pass) {
    if (pass.iterations <= 0)
        return;
    const int w = g.value.width, h = g.value.height;
    Image eh = image(w, h), ev = image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            eh.at(x, y) =
                x + 1 < w ? weight(g.colorH.at(x, y), g.value.at(x + 1, y) - g.value.at(x, y), pass) : 0.0;
            ev.at(x, y) =
                y + 1 < h ? weight(g.colorV.at(x, y), g.value.at(x, y + 1) - g.value.at(x, y), pass) : 0.0;
        }
    Image sum = g.dataSum, wt = g.dataWeight;
    for (int t = 0; t < pass.iterations; ++t) {
        const double scale = pass.lambda * 1.5 * std::pow(4.0, pass.iterations - 1 - t) /
                             (std::pow(4.0, pass.iterations) - 1.0);
        for (Image* plane : {&sum, &wt}) {
            for (int y = 0; y < h; ++y) {
                std::vector<double> r(static_cast<std::size_t>(w)), e(static_cast<std::size_t>(w));
                for (int x = 0; x < w; ++x) {
                    r[x] = plane->at(x, y);
                    e[x] = scale * eh.at(x, y);
                }
                solveLine(r, e);
                for (int x = 0; x < w; ++x)
                    plane->at(x, y) = r[x];
            }
        }
        for (Image* plane : {&sum, &wt}) {
            for (int x = 0; x < w; ++x) {
                std::vector<double> r(static_cast<std::size_t>(h)), e(static_cast<std::size_t>(h));
                for (int y = 0; y < h; ++y) {
                    r[y] = plane->at(x, y);
                    e[y] = scale * ev.at(x, y);
                }
                solveLine(r, e);
                for (int y = 0; y < h; ++y)
                    plane->at(x, y) = r[y];
            }
        }
    }
    ratio(sum, wt, g);
}

// The guide reduced to the sensor's size as processing's resized() does it: exact halvings with area
// averaging while the size allows, then one area (shrinking) or bilinear step.
inline cv::Mat reduced(const cv::Mat& source, cv::Size size) {
    if (source.size() == size)
        return source;
    const bool shrinks = 2 * size.width <= source.cols || 2 * size.height <= source.rows;
    cv::Mat current = source;
    while (shrinks && 2 * size.width <= current.cols && 2 * size.height <= current.rows &&
           current.cols % 2 == 0 && current.rows % 2 == 0) {
        cv::Mat half;
        cv::resize(current, half, {current.cols / 2, current.rows / 2}, 0, 0, cv::INTER_AREA);
        current = half;
    }
    if (current.size() == size)
        return current;
    cv::Mat out;
    cv::resize(current, out, size, 0, 0, shrinks ? cv::INTER_AREA : cv::INTER_LINEAR);
    return out;
}

// Where each output coordinate samples the sensor axis (OpenCV's INTER_LINEAR convention).
inline void tap(int d, int sourceSize, int destinationSize, int& first, int& second, double& f) {
    const double s = std::clamp((d + 0.5) * sourceSize / destinationSize - 0.5, 0.0, sourceSize - 1.0);
    first = static_cast<int>(std::floor(s));
    second = std::min(first + 1, sourceSize - 1);
    f = static_cast<float>(s - first); // the implementation keeps the fraction in float
}

inline double medianOf9(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + 4, v.end());
    return v[4];
}

// Each measured pixel whose 3 x 3 neighbourhood's measured depths span more than `range` takes the nearer
// of their minimum and maximum (kept at a tie); the image's edge rows and columns repeated beyond it.
inline frame::Plane<double> snapEdges(const frame::Plane<double>& in, double range) {
    frame::Plane<double> out = in;
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            double low = std::numeric_limits<double>::infinity(), high = 0.0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const double v =
                        in.at(std::clamp(x + dx, 0, in.width - 1), std::clamp(y + dy, 0, in.height - 1));
                    if (v > 0.0) {
                        low = std::min(low, v);
                        high = std::max(high, v);
                    }
                }
            const double v = in.at(x, y);
            if (v > 0.0 && high - low > range && v - low != high - v)
                out.at(x, y) = v - low < high - v ? low : high;
        }
    return out;
}

inline frame::Plane<double> upsample(const frame::DepthData& depth, ColorView guide,
                                     const GlobalSmootherParams& p) {
    const frame::Plane<float>& d = depth.depthMeters;
    const int sw = d.width, sh = d.height, w = guide.width, h = guide.height;
    frame::Plane<double> out(w, h);
    const bool hasConfidence = depth.confidence.pixels.size() == d.pixels.size();
    const double levels[3] = {0.0, 0.5, 1.0};
    double sum = 0.0, total = 0.0, validSum = 0.0, validCount = 0.0;
    std::vector<int> valid(d.pixels.size(), 0);
    for (std::size_t i = 0; i < d.pixels.size(); ++i)
        if (measured(d.pixels[i])) {
            valid[i] = 1;
            const double c = hasConfidence ? levels[std::min<int>(depth.confidence.pixels[i], 2)] : 1.0;
            sum += c * d.pixels[i];
            total += c;
            validSum += d.pixels[i];
            validCount += 1.0;
        }
    if (validCount == 0.0)
        return out;
    const bool trustAll = total <= 0.0;
    const double offset = trustAll ? validSum / validCount : sum / total;
    Grid sensor = grid(sw, sh);
    for (std::size_t i = 0; i < d.pixels.size(); ++i) {
        const double c = !valid[i]                    ? 0.0
                         : trustAll || !hasConfidence ? 1.0
                                                      : levels[std::min<int>(depth.confidence.pixels[i], 2)];
        sensor.dataWeight.v[i] = c;
        sensor.dataSum.v[i] = c > 0.0 ? c * (d.pixels[i] - offset) : 0.0;
    }
    const cv::Mat full(h, w, CV_8UC3, const_cast<std::uint8_t*>(guide.pixels),
                       static_cast<std::size_t>(guide.stride));
    const cv::Mat small = reduced(full, {sw, sh}).clone();
    colorDistances({small.ptr<std::uint8_t>(0), sw, sh, static_cast<std::ptrdiff_t>(small.step[0])}, sensor);
    ratio(sensor.dataSum, sensor.dataWeight, sensor);
    runPass(sensor, p.sensorColor);
    runPass(sensor, p.sensorDepth);

    Grid output = grid(w, h);
    Image measuredWeight = image(w, h);
    const double big = std::numeric_limits<float>::max();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int x0, x1, y0, y1;
            double fx, fy;
            tap(x, sw, w, x0, x1, fx);
            tap(y, sh, h, y0, y1, fy);
            double s = 0.0, m = 0.0, lo = big, hi = -big;
            for (const auto& [sx, sy, f] :
                 {std::tuple{x0, y0, (1 - fx) * (1 - fy)}, std::tuple{x1, y0, fx * (1 - fy)},
                  std::tuple{x0, y1, (1 - fx) * fy}, std::tuple{x1, y1, fx * fy}}) {
                const double v = valid[static_cast<std::size_t>(sy) * sw + sx], z = sensor.value.at(sx, sy);
                s += f * v * z;
                m += f * v;
                if (v > 0.0) {
                    lo = std::min(lo, z);
                    hi = std::max(hi, z);
                }
            }
            const double spread = hi > lo && p.footprintSigma > 0.0f ? (hi - lo) / p.footprintSigma : 0.0;
            const double factor = 1.0 / (1.0 + spread * spread);
            measuredWeight.at(x, y) = m;
            output.dataSum.at(x, y) = s * factor;
            output.dataWeight.at(x, y) = m * factor;
        }
    colorDistances(guide, output);
    ratio(output.dataSum, output.dataWeight, output);
    runPass(output, p.outputColor);
    runPass(output, p.outputDepth);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double q = output.value.at(x, y);
            if ((p.medianPixels == 3) && w >= 3 && h >= 3) {
                std::vector<double> window;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        window.push_back(
                            output.value.at(std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1)));
                q = medianOf9(window);
            }
            const double dw = output.dataWeight.at(x, y);
            const double own = (dw > 0.0 ? output.dataSum.at(x, y) / dw : 0.0) + offset;
            q += offset;
            out.at(x, y) = !(measuredWeight.at(x, y) >= 0.5) ? 0.0
                           : measured(q)                     ? q
                           : measured(own)                   ? own
                                                             : 0.0;
        }
    return p.edgeSnapRange > 0.0f ? snapEdges(out, p.edgeSnapRange) : out;
}

} // namespace dc::processing::reference
