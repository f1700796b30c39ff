#include "processing/registration.h"

#include "processing/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>

namespace dc::processing {

namespace {

// The colour-sensor position of every depth sample, and half the side of the square it covers in the
// colour image (see FloatTarget); z <= 0 where it lands nowhere near the colour image.
struct Projected {
    float x = 0, y = 0, z = 0, half = 0;
};

bool insideImage(const Projected& p, int width, int height) {
    return p.x >= -0.5f && p.y >= -0.5f && p.x < width - 0.5f && p.y < height - 0.5f;
}

// The largest ideal radius the image's corners and edge midpoints come from, a fifth more.
double lensRadius2(const frame::CameraModel& camera) {
    if (camera.lens.model == frame::LensModel::None)
        return std::numeric_limits<double>::infinity();
    const frame::Intrinsics& k = camera.intrinsics;
    double worst = 0.0;
    for (const double u : {-0.5, 0.5 * (k.width - 1), k.width - 0.5})
        for (const double v : {-0.5, 0.5 * (k.height - 1), k.height - 0.5}) {
            const auto ray = frame::pixelRay(camera, u, v);
            worst = std::max(worst, ray[0] * ray[0] + ray[1] * ray[1]);
        }
    return 1.44 * worst;
}

// The colour camera and the transform in single precision, as projectRow uses them: positions stay within
// a thousandth of a colour pixel of the double-precision model, and float lanes are twice as wide.
struct FloatTarget {
    float fx, fy, cx, cy;
    std::array<float, 5> k;         // the lens coefficients
    float maxRadius2;               // see ColourProjection
    float left, top, right, bottom; // where a sample still lands: the image and its margin
    // Half the side, in colour pixels, of the square a sample covers, is this times z / zc (at least half
    // a pixel): a depth pixel at depth z spans z / fDepth meters, which the colour camera at distance zc
    // sees as fColour z / (fDepth zc) pixels. A fifth more covers the stretch of lens distortion and
    // slanted surfaces, so neighbouring samples of one surface leave no gap for a farther one to show
    // through.
    float halfPerDepthOverColourZ;
    std::array<float, 3> t; // the translation, meters

    explicit FloatTarget(const ColourProjection& target)
        : fx(static_cast<float>(target.colourCamera.intrinsics.fx)),
          fy(static_cast<float>(target.colourCamera.intrinsics.fy)),
          cx(static_cast<float>(target.colourCamera.intrinsics.cx)),
          cy(static_cast<float>(target.colourCamera.intrinsics.cy)), k{},
          maxRadius2(static_cast<float>(target.maxRadius2)),
          left(static_cast<float>(-0.5 - target.marginPixels)), top(left),
          right(static_cast<float>(target.colourCamera.intrinsics.width - 0.5 + target.marginPixels)),
          bottom(static_cast<float>(target.colourCamera.intrinsics.height - 0.5 + target.marginPixels)),
          halfPerDepthOverColourZ(static_cast<float>(target.halfPerDepthOverColourZ)), t{} {
        for (std::size_t i = 0; i < 5; ++i)
            k[i] = static_cast<float>(target.colourCamera.lens.coefficients[i]);
        for (std::size_t i = 0; i < 3; ++i)
            t[i] = static_cast<float>(target.depthToColour.translationMeters[i]);
    }
};

// The colour-sensor position of every depth sample, and for each depth row the colour rows its samples'
// squares reach (lowest, highest), so that a band of colour rows visits only the depth rows that reach it.
struct ProjectedDepth {
    std::vector<Projected> points;
    std::vector<std::pair<int, int>> rowReach;
};

// The depth rays through one row's pixels at z = 1, in the colour sensor's axes (R applied), one array per
// axis. A pinhole ray is linear in u, so the row costs one rotation; a lens is inverted per pixel.
struct RowRays {
    std::vector<float> x, y, z;

    void fill(const frame::CameraModel& depthCamera, const frame::RigidTransform& toColour, int v,
              int width) {
        const auto rotate = [&r = toColour.rotation](const std::array<double, 3>& p) {
            return std::array<double, 3>{r[0] * p[0] + r[1] * p[1] + r[2] * p[2],
                                         r[3] * p[0] + r[4] * p[1] + r[5] * p[2],
                                         r[6] * p[0] + r[7] * p[1] + r[8] * p[2]};
        };
        for (auto* axis : {&x, &y, &z})
            axis->resize(static_cast<std::size_t>(width));
        const frame::Intrinsics& k = depthCamera.intrinsics;
        if (depthCamera.lens.model == frame::LensModel::None) {
            const auto origin = rotate({-k.cx / k.fx, (v - k.cy) / k.fy, 1.0});
            const auto step = rotate({1.0 / k.fx, 0.0, 0.0});
            for (int u = 0; u < width; ++u) {
                const auto i = static_cast<std::size_t>(u);
                x[i] = static_cast<float>(origin[0] + u * step[0]);
                y[i] = static_cast<float>(origin[1] + u * step[1]);
                z[i] = static_cast<float>(origin[2] + u * step[2]);
            }
            return;
        }
        for (int u = 0; u < width; ++u) {
            const auto ray = rotate(frame::pixelRay(depthCamera, u, v));
            const auto i = static_cast<std::size_t>(u);
            x[i] = static_cast<float>(ray[0]);
            y[i] = static_cast<float>(ray[1]);
            z[i] = static_cast<float>(ray[2]);
        }
    }
};

// floor and ceil of a coordinate near the image, through one truncating conversion: x86-64's baseline
// (SSE2) has no rounding instruction, and std::floor becomes a sequence several times as long.
int floorOf(float v) {
    const auto i = static_cast<int>(v);
    return i - static_cast<int>(v < static_cast<float>(i));
}
int ceilOf(float v) {
    const auto i = static_cast<int>(v);
    return i + static_cast<int>(v > static_cast<float>(i));
}

// One row of samples projected into the colour image. Every lane is computed and the samples that land
// nowhere are written as z = 0, without a branch, so that the loop vectorises; only a colour lens given as
// the inverse polynomial (iterative to apply) goes through the double-precision model.
template <frame::LensModel kLens>
void projectRow(const float* depth, const RowRays& rays, int width, const FloatTarget& c,
                const frame::Lens& lens, Projected* out) {
    for (int u = 0; u < width; ++u) {
        const auto i = static_cast<std::size_t>(u);
        const float z = depth[i];
        const float qz = rays.z[i] * z + c.t[2];
        const float inverseZ = 1.0f / qz;
        float x = (rays.x[i] * z + c.t[0]) * inverseZ;
        float y = (rays.y[i] * z + c.t[1]) * inverseZ;
        const float r2 = x * x + y * y;
        if constexpr (kLens == frame::LensModel::BrownConrady) {
            const float radial = 1.0f + r2 * (c.k[0] + r2 * (c.k[1] + r2 * c.k[4]));
            const float xd = x * radial + 2.0f * c.k[2] * x * y + c.k[3] * (r2 + 2.0f * x * x);
            y = y * radial + c.k[2] * (r2 + 2.0f * y * y) + 2.0f * c.k[3] * x * y;
            x = xd;
        } else if constexpr (kLens == frame::LensModel::InverseBrownConrady) {
            const auto d = frame::distortPoint(lens, x, y);
            x = static_cast<float>(d[0]);
            y = static_cast<float>(d[1]);
        }
        const float px = c.fx * x + c.cx;
        const float py = c.fy * y + c.cy;
        // Comparisons that a NaN (no depth, a lens that cannot be inverted) fails as well.
        const bool lands = (z > 0.0f) & (z < std::numeric_limits<float>::infinity()) & (qz > 0.0f) &
                           (r2 <= c.maxRadius2) & (px >= c.left) & (py >= c.top) & (px < c.right) &
                           (py < c.bottom);
        // A square wider than any image is as good as a larger one, and keeps the conversions in range.
        const float half = std::min(std::max(0.5f, c.halfPerDepthOverColourZ * z * inverseZ), 16384.0f);
        out[i] = lands ? Projected{px, py, qz, half} : Projected{};
    }
}

ProjectedDepth projectAll(const frame::Plane<float>& depth, const ColourProjection& target) {
    ProjectedDepth out{std::vector<Projected>(depth.pixels.size()),
                       std::vector<std::pair<int, int>>(static_cast<std::size_t>(depth.height),
                                                        {std::numeric_limits<int>::max(), -1})};
    const FloatTarget floatTarget(target);
    const frame::Lens& lens = target.colourCamera.lens;
    const auto row = lens.model == frame::LensModel::None ? projectRow<frame::LensModel::None>
                     : lens.model == frame::LensModel::BrownConrady
                         ? projectRow<frame::LensModel::BrownConrady>
                         : projectRow<frame::LensModel::InverseBrownConrady>;
    parallelRanges(depth.height, 16, [&](int rowBegin, int rowEnd) {
        RowRays rays;
        for (int v = rowBegin; v < rowEnd; ++v) {
            rays.fill(target.depthCamera, target.depthToColour, v, depth.width);
            const std::size_t first = static_cast<std::size_t>(v) * static_cast<std::size_t>(depth.width);
            Projected* points = &out.points[first];
            row(&depth.pixels[first], rays, depth.width, floatTarget, lens, points);
            // ceil and floor are monotonic: the row's extremes are rounded once, not each sample's.
            float low = std::numeric_limits<float>::infinity(), high = -low;
            for (int u = 0; u < depth.width; ++u)
                if (points[u].z > 0.0f) {
                    low = std::min(low, points[u].y - points[u].half);
                    high = std::max(high, points[u].y + points[u].half);
                }
            if (low <= high)
                out.rowReach[static_cast<std::size_t>(v)] = {ceilOf(low), floorOf(high)};
        }
    });
    return out;
}

// The nearest depth over each colour pixel, every sample covering its square. Each piece owns a band of
// colour rows, so no two threads write one pixel; each also clears its band, which would otherwise be
// megabytes cleared on one thread.
std::unique_ptr<float[]> nearestDepth(const ProjectedDepth& projected, int depthWidth, int width,
                                      int height) {
    auto zbuffer = std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(width) * height);
    const std::size_t rowLength = static_cast<std::size_t>(depthWidth);
    parallelRanges(height, 32, [&](int bandBegin, int bandEnd) {
        const auto row = [width](int y) {
            return static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        };
        std::fill(&zbuffer[row(bandBegin)], &zbuffer[row(bandEnd)], std::numeric_limits<float>::infinity());
        for (std::size_t v = 0; v < projected.rowReach.size(); ++v) {
            const auto [low, high] = projected.rowReach[v];
            if (high < bandBegin || low >= bandEnd)
                continue;
            for (std::size_t i = v * rowLength; i < (v + 1) * rowLength; ++i) {
                const Projected& p = projected.points[i];
                if (!(p.z > 0.0f))
                    continue;
                const int y0 = std::max(bandBegin, ceilOf(p.y - p.half));
                const int y1 = std::min(bandEnd - 1, floorOf(p.y + p.half));
                const int x0 = std::max(0, ceilOf(p.x - p.half));
                const int x1 = std::min(width - 1, floorOf(p.x + p.half));
                // Column by column: a square is two or three pixels wide, too few for vector lanes, and the
                // vectorised row loop's wide stores stall the next sample's loads of the pixels they share.
                for (int x = x0; x <= x1; ++x) {
                    float* column = zbuffer.get() + x;
                    for (int y = y0; y <= y1; ++y) {
                        float& nearest =
                            column[static_cast<std::size_t>(y) * static_cast<std::size_t>(width)];
                        nearest = std::min(nearest, p.z);
                    }
                }
            }
        }
    });
    return zbuffer;
}

bool proportional(const frame::Intrinsics& a, const frame::Intrinsics& b) {
    const auto same = [](double p, int pw, double q, int qw) {
        return std::abs(p / pw - q / qw) <= 1e-12 * std::max(1.0, std::abs(p / pw));
    };
    return same(a.fx, a.width, b.fx, b.width) && same(a.fy, a.height, b.fy, b.height) &&
           same(a.cx, a.width, b.cx, b.width) && same(a.cy, a.height, b.cy, b.height);
}

} // namespace

ColourProjection colourProjection(const frame::RigCalibration& rig, const frame::Intrinsics& depthIntrinsics,
                                  int colourWidth, int colourHeight) {
    ColourProjection p;
    p.depthCamera = {depthIntrinsics, rig.depth.lens};
    p.colourCamera = {rig.colour.intrinsics.scaledTo(colourWidth, colourHeight), rig.colour.lens};
    p.depthToColour = rig.depthToColour;
    const double pixelsPerDepthPixel = std::max(p.colourCamera.intrinsics.fx / depthIntrinsics.fx,
                                                p.colourCamera.intrinsics.fy / depthIntrinsics.fy);
    // Samples just outside the image still cover its border pixels: twice a footprint is ample.
    p.marginPixels = 2.0 * pixelsPerDepthPixel + 1.0;
    p.maxRadius2 = lensRadius2(p.colourCamera);
    p.halfPerDepthOverColourZ = 0.6 * pixelsPerDepthPixel;
    return p;
}

bool shaderRegistrable(const frame::RigCalibration& rig) {
    return rig.depth.lens.model == frame::LensModel::None &&
           rig.colour.lens.model != frame::LensModel::InverseBrownConrady;
}

namespace {

// The depth samples in the colour sensor's image, and the z-buffer they make there.
struct ColourView {
    std::vector<Projected> points;
    std::unique_ptr<float[]> zbuffer; // the colour image's size
};

ColourView viewFromColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                          const frame::Intrinsics& depthIntrinsics, int colourWidth, int colourHeight) {
    const ColourProjection target = colourProjection(rig, depthIntrinsics, colourWidth, colourHeight);
    ProjectedDepth projected = projectAll(depth, target);
    std::unique_ptr<float[]> zbuffer = nearestDepth(projected, depth.width, colourWidth, colourHeight);
    return {std::move(projected.points), std::move(zbuffer)};
}

ColourView viewFromColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig, int colourWidth,
                          int colourHeight) {
    return viewFromColour(depth, rig, rig.depth.intrinsics.scaledTo(depth.width, depth.height), colourWidth,
                          colourHeight);
}

bool registrable(const frame::Plane<float>& depth, const frame::RigCalibration& rig, int colourWidth,
                 int colourHeight) {
    return !depth.empty() && colourWidth > 0 && colourHeight > 0 && rig.depth.intrinsics.valid() &&
           rig.colour.intrinsics.valid();
}

} // namespace

namespace {

// The colour pixel nearest sample i's projection when the colour camera sees the sample there (nothing
// nearer hides it), else kUnseen.
std::int32_t seenPixel(const ColourView& view, std::size_t i, int colourWidth, int colourHeight) {
    const Projected& p = view.points[i];
    if (!(p.z > 0.0f) || !insideImage(p, colourWidth, colourHeight))
        return Registration::kUnseen;
    // Projections start at -0.5, so truncating x + 0.5 rounds to the nearest pixel.
    const auto x = std::min(static_cast<std::int32_t>(p.x + 0.5f), colourWidth - 1);
    const auto y = std::min(static_cast<std::int32_t>(p.y + 0.5f), colourHeight - 1);
    const std::int32_t pixel = y * colourWidth + x;
    return p.z > view.zbuffer[static_cast<std::size_t>(pixel)] + sameSurfaceMeters(p.z)
               ? Registration::kUnseen
               : pixel;
}

} // namespace

Registration registerDepth(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                           int colourWidth, int colourHeight) {
    Registration out{colourWidth, colourHeight,
                     std::vector<std::int32_t>(depth.pixels.size(), Registration::kUnseen),
                     frame::Plane<std::uint8_t>(depth.width, depth.height)};
    if (!registrable(depth, rig, colourWidth, colourHeight))
        return out;
    const ColourView view = viewFromColour(depth, rig, colourWidth, colourHeight);
    parallelRanges(static_cast<int>(depth.pixels.size()), 4096, [&](int begin, int end) {
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
            out.colourPixel[i] = seenPixel(view, i, colourWidth, colourHeight);
            out.seen.pixels[i] = out.colourPixel[i] != Registration::kUnseen;
        }
    });
    return out;
}

frame::Plane<float> alignDepthToColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                                       int colourWidth, int colourHeight) {
    if (!registrable(depth, rig, colourWidth, colourHeight))
        return frame::Plane<float>(std::max(colourWidth, 0), std::max(colourHeight, 0));
    const ColourView view = viewFromColour(depth, rig, colourWidth, colourHeight);
    frame::Plane<float> aligned(colourWidth, colourHeight);
    std::transform(view.zbuffer.get(), view.zbuffer.get() + aligned.pixels.size(), aligned.pixels.begin(),
                   [](float z) { return std::isfinite(z) ? z : 0.0f; });
    return aligned;
}

bool isSingleCamera(const frame::RigCalibration& rig) {
    return rig.depthToColour.isIdentity() && rig.depth.lens == rig.colour.lens &&
           proportional(rig.depth.intrinsics, rig.colour.intrinsics);
}

bool shaderCanColour(const frame::RigCalibration* rig) {
    return !rig || isSingleCamera(*rig) || shaderRegistrable(*rig);
}

PointColours framePointColours(const frame::Frame& frame, const frame::Plane<float>& depth,
                               CameraColourTable& table) {
    if (!frame.rig)
        return framePointColours(frame, depth, {}, table);
    return framePointColours(frame, depth, frame.rig->depth.intrinsics.scaledTo(depth.width, depth.height),
                             table);
}

PointColours framePointColours(const frame::Frame& frame, const frame::Plane<float>& depth,
                               const frame::Intrinsics& depthIntrinsics, CameraColourTable& table) {
    const frame::CapturedImage& image = frame.capturedImage;
    if (!frame.rig || isSingleCamera(*frame.rig))
        return {std::make_shared<const RgbImage>(pointColours(image, depth.width, depth.height, table)),
                nullptr};
    auto colours = std::make_shared<RgbImage>(
        RgbImage{depth.width, depth.height, std::vector<std::uint8_t>(depth.pixels.size() * 3, kUnseenGray)});
    auto seen = std::make_shared<frame::Plane<std::uint8_t>>(depth.width, depth.height);
    if (!table.use(image) || !registrable(depth, *frame.rig, image.width, image.height))
        return {std::move(colours), std::move(seen)};
    const ColourView view = viewFromColour(depth, *frame.rig, depthIntrinsics, image.width, image.height);
    const auto store = [&pixels = colours->pixels](std::size_t i, std::uint32_t rgba) {
        pixels[i * 3] = static_cast<std::uint8_t>(rgba);
        pixels[i * 3 + 1] = static_cast<std::uint8_t>(rgba >> 8);
        pixels[i * 3 + 2] = static_cast<std::uint8_t>(rgba >> 16);
    };
    // The table fills itself as colours are first met, which one thread must do alone: the threads look up
    // what it holds and leave the few samples it lacks (most only in a scene's first frames) for after.
    std::mutex missedMutex;
    std::vector<std::pair<std::size_t, std::int32_t>> missed;
    parallelRanges(static_cast<int>(depth.pixels.size()), 4096, [&](int begin, int end) {
        std::vector<std::pair<std::size_t, std::int32_t>> mine;
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
            const std::int32_t pixel = seenPixel(view, i, image.width, image.height);
            if (pixel == Registration::kUnseen)
                continue;
            seen->pixels[i] = 1;
            if (const auto rgba = table.filledRgba(pixel % image.width, pixel / image.width))
                store(i, *rgba);
            else
                mine.emplace_back(i, pixel);
        }
        const std::lock_guard lock(missedMutex);
        missed.insert(missed.end(), mine.begin(), mine.end());
    });
    for (const auto& [i, pixel] : missed)
        store(i, table.rgba(pixel % image.width, pixel / image.width));
    return {std::move(colours), std::move(seen)};
}

bool sampleSeenByColour(const frame::Frame& frame, const frame::Plane<float>& depth,
                        const frame::Intrinsics& depthIntrinsics, int u, int v) {
    if (!frame.rig || isSingleCamera(*frame.rig))
        return true;
    const frame::CapturedImage& image = frame.capturedImage;
    if (image.empty() || !registrable(depth, *frame.rig, image.width, image.height) || u < 0 || v < 0 ||
        u >= depth.width || v >= depth.height)
        return false;
    const ProjectedDepth projected =
        projectAll(depth, colourProjection(*frame.rig, depthIntrinsics, image.width, image.height));
    const Projected& p = projected.points[static_cast<std::size_t>(v) * depth.width + u];
    if (!(p.z > 0.0f) || !insideImage(p, image.width, image.height))
        return false;
    const int x = std::min(static_cast<int>(p.x + 0.5f), image.width - 1);
    const int y = std::min(static_cast<int>(p.y + 0.5f), image.height - 1);
    float nearest = std::numeric_limits<float>::infinity();
    for (const Projected& q : projected.points)
        if (q.z > 0.0f && ceilOf(q.x - q.half) <= x && x <= floorOf(q.x + q.half) &&
            ceilOf(q.y - q.half) <= y && y <= floorOf(q.y + q.half))
            nearest = std::min(nearest, q.z);
    return !(p.z > nearest + sameSurfaceMeters(p.z));
}

RgbaImage seenColourOverlay(const PointColours& colours) {
    const RgbImage& rgb = *colours.colours;
    const std::size_t n = static_cast<std::size_t>(rgb.width) * static_cast<std::size_t>(rgb.height);
    RgbaImage out{rgb.width, rgb.height, std::vector<std::uint8_t>(n * 4, 0)};
    for (std::size_t i = 0; i < n; ++i) {
        if (colours.seen && colours.seen->pixels[i] == 0)
            continue;
        std::copy_n(&rgb.pixels[i * 3], 3, &out.pixels[i * 4]);
        out.pixels[i * 4 + 3] = 255;
    }
    return out;
}

RgbImage colourAlignedToDepth(const frame::Frame& frame, const frame::Plane<float>& depth, int width,
                              int height, CameraColourTable& table) {
    frame::Plane<float> nearest(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            nearest.at(x, y) = depth.at(x * depth.width / width, y * depth.height / height);
    return *framePointColours(frame, nearest, table).colours;
}

} // namespace dc::processing
