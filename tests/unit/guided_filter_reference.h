#pragma once

// The masked, fit-weighted guided filter written straight from its definition in double precision with
// two-pass (mean-centred) window statistics and brute-force windows: slow, but with no running sums, no
// global centring and no float storage, so it shows what the fast implementation should compute.

#include "frame/frame.h"
#include "processing/guided_filter.h"

#include "tests/unit/reference_depth.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dc::processing::reference {

struct Window {
    bool has = false;
    double a = 0, b = 0, weight = 0;
};

inline Window windowModel(const frame::Plane<float>& guide, const frame::Plane<float>& depth,
                          const std::vector<double>& w, int cx, int cy, const GuidedFilterParams& p) {
    const int r = std::max(p.radius, 1);
    const int x0 = std::max(cx - r, 0), x1 = std::min(cx + r, guide.width - 1);
    const int y0 = std::max(cy - r, 0), y1 = std::min(cy + r, guide.height - 1);
    double n = 0, sg = 0, sz = 0;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const double wi = w[static_cast<std::size_t>(y) * guide.width + x];
            n += wi;
            sg += wi * guide.at(x, y);
            sz += wi > 0 ? wi * depth.at(x, y) : 0.0;
        }
    if (n < 1e-3)
        return {};
    const double mg = sg / n, mz = sz / n;
    double vg = 0, vz = 0, cov = 0;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const double wi = w[static_cast<std::size_t>(y) * guide.width + x];
            if (wi <= 0)
                continue;
            const double dg = guide.at(x, y) - mg, dz = depth.at(x, y) - mz;
            vg += wi * dg * dg;
            vz += wi * dz * dz;
            cov += wi * dg * dz;
        }
    vg /= n, vz /= n, cov /= n;
    const double a = cov / (vg + p.epsilon);
    double weight = 1.0;
    if (p.fitWeighted) {
        const double cost = std::max(vz - 2 * a * cov + a * a * vg + p.epsilon * a * a, 0.0);
        const double t = 1.0 + cost / (static_cast<double>(p.fitNoise) * p.fitNoise);
        weight = std::max(1.0 / (t * t), 1e-30);
    }
    return {true, a, mz - a * mg, weight};
}

// Output depth per pixel in double (0 where the pixel has no measurement of its own).
inline std::vector<double> filter(const frame::Plane<float>& guide, const frame::Plane<float>& depth,
                                  const frame::Plane<float>& weight, const GuidedFilterParams& p) {
    const int width = guide.width, height = guide.height;
    std::vector<double> w(depth.pixels.size());
    for (std::size_t i = 0; i < w.size(); ++i) {
        const double wi = std::clamp(static_cast<double>(weight.pixels[i]), 0.0, 1.0);
        w[i] = measured(depth.pixels[i]) && wi >= 1e-3 ? wi : 0.0;
    }
    std::vector<Window> windows(w.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            windows[static_cast<std::size_t>(y) * width + x] = windowModel(guide, depth, w, x, y, p);
    const int r = std::max(p.radius, 1);
    std::vector<double> out(w.size(), 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * width + x;
            if (w[i] < 0.5)
                continue;
            double sa = 0, sb = 0, sw = 0;
            for (int ky = std::max(y - r, 0); ky <= std::min(y + r, height - 1); ++ky)
                for (int kx = std::max(x - r, 0); kx <= std::min(x + r, width - 1); ++kx) {
                    const Window& k = windows[static_cast<std::size_t>(ky) * width + kx];
                    if (!k.has)
                        continue;
                    sa += k.weight * k.a;
                    sb += k.weight * k.b;
                    sw += k.weight;
                }
            const double q = (sa * guide.pixels[i] + sb) / sw;
            out[i] = measured(q) ? q : depth.pixels[i];
        }
    return out;
}

} // namespace dc::processing::reference
