#include "processing/registration.h"

#include "processing/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace dc::processing {

namespace {

// Two samples of one surface that cover the same colour pixel differ in depth by the surface's slope
// over a depth pixel, plus sensor noise (about 2 cm at 4 m for the noisiest sensors we read): within this
// much they are the same surface, and the farther one is not hidden.
float sameSurfaceMeters(float colourZ) {
    return 0.01f + 0.02f * colourZ;
}

// The colour-sensor position of every depth sample; z <= 0 where it lands nowhere near the colour image.
struct Projected {
    float x = 0, y = 0, z = 0;
    bool inside = false; // within the colour image (else only near it, covering its border pixels)
};

// Where depth samples may land: the colour camera, how far outside its image a sample still counts (it
// covers border pixels), and the ideal normalised radius (squared) beyond which the lens polynomial no
// longer describes the image: evaluated far outside the field of view it folds back and would put a point
// from behind the camera's shoulder into the picture.
struct ColourTarget {
    frame::CameraModel camera;
    double marginPixels = 0.0;
    double maxRadius2 = std::numeric_limits<double>::infinity();
};

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

std::vector<Projected> projectAll(const frame::Plane<float>& depth, const frame::CameraModel& depthCamera,
                                  const ColourTarget& target, const frame::RigidTransform& toColour) {
    std::vector<Projected> out(depth.pixels.size());
    const frame::CameraModel& colourCamera = target.camera;
    const frame::Intrinsics& kc = colourCamera.intrinsics;
    const double margin = target.marginPixels;
    const frame::Intrinsics& kd = depthCamera.intrinsics;
    const bool pinhole = depthCamera.lens.model == frame::LensModel::None;
    parallelRanges(depth.height, 16, [&](int rowBegin, int rowEnd) {
        for (int v = rowBegin; v < rowEnd; ++v)
            for (int u = 0; u < depth.width; ++u) {
                const float z = depth.at(u, v);
                if (!(z > 0.0f) || !std::isfinite(z))
                    continue;
                const auto ray = pinhole
                                     ? std::array<double, 3>{(u - kd.cx) / kd.fx, (v - kd.cy) / kd.fy, 1.0}
                                     : frame::pixelRay(depthCamera, u, v);
                const auto q = toColour.apply({ray[0] * z, ray[1] * z, z});
                if (!(q[2] > 0.0) || (q[0] * q[0] + q[1] * q[1]) / (q[2] * q[2]) > target.maxRadius2)
                    continue;
                const auto pixel = frame::projectPoint(colourCamera, q);
                if (!pixel)
                    continue;
                const auto [x, y] = *pixel;
                // Written so that a NaN (from a lens that cannot be inverted) fails it too.
                if (!(x >= -0.5 - margin && y >= -0.5 - margin && x < kc.width - 0.5 + margin &&
                      y < kc.height - 0.5 + margin))
                    continue;
                const bool inside = x >= -0.5 && y >= -0.5 && x < kc.width - 0.5 && y < kc.height - 0.5;
                out[static_cast<std::size_t>(v) * depth.width + u] = {
                    static_cast<float>(x), static_cast<float>(y), static_cast<float>(q[2]), inside};
            }
    });
    return out;
}

// Calls visit(sample, half) for each projected sample of depth row v, where half is half the side, in
// colour pixels, of the square the sample covers: a depth pixel at depth z spans z / fDepth meters, which
// the colour camera at distance zc sees as fColour z / (fDepth zc) pixels. A fifth more covers the stretch
// of lens distortion and slanted surfaces, so neighbouring samples of one surface leave no gap for a
// farther one to show through.
template <class Visit>
void forEachInRow(const std::vector<Projected>& points, const frame::Plane<float>& depth, int v,
                  double pixelsPerDepthPixel, Visit&& visit) {
    const std::size_t rowBegin = static_cast<std::size_t>(v) * static_cast<std::size_t>(depth.width);
    for (std::size_t i = rowBegin; i < rowBegin + static_cast<std::size_t>(depth.width); ++i) {
        const Projected& p = points[i];
        if (p.z > 0.0f)
            visit(p, std::max(0.5, 0.6 * pixelsPerDepthPixel * depth.pixels[i] / p.z));
    }
}

// The colour rows each depth row's samples reach (lowest, highest), so that a band of colour rows visits
// only the depth rows that reach it instead of every sample.
std::vector<std::pair<double, double>>
rowReach(const std::vector<Projected>& points, const frame::Plane<float>& depth, double pixelsPerDepthPixel) {
    std::vector<std::pair<double, double>> reach(
        static_cast<std::size_t>(depth.height),
        {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
    parallelRanges(depth.height, 16, [&](int begin, int end) {
        for (int v = begin; v < end; ++v) {
            auto& [low, high] = reach[static_cast<std::size_t>(v)];
            forEachInRow(points, depth, v, pixelsPerDepthPixel, [&](const Projected& p, double half) {
                low = std::min(low, p.y - half);
                high = std::max(high, p.y + half);
            });
        }
    });
    return reach;
}

// The nearest depth over each colour pixel, every sample covering its footprint. Each piece owns a band of
// colour rows, so no two threads write one pixel.
std::vector<float> nearestDepth(const std::vector<Projected>& points, const frame::Plane<float>& depth,
                                double pixelsPerDepthPixel, int width, int height) {
    std::vector<float> zbuffer(static_cast<std::size_t>(width) * height,
                               std::numeric_limits<float>::infinity());
    const auto reach = rowReach(points, depth, pixelsPerDepthPixel);
    parallelRanges(height, 32, [&](int bandBegin, int bandEnd) {
        for (int v = 0; v < depth.height; ++v) {
            const auto [low, high] = reach[static_cast<std::size_t>(v)];
            if (high < bandBegin - 1.0 || low > bandEnd)
                continue;
            forEachInRow(points, depth, v, pixelsPerDepthPixel, [&](const Projected& p, double half) {
                const int y0 = std::max(bandBegin, static_cast<int>(std::ceil(p.y - half)));
                const int y1 = std::min(bandEnd - 1, static_cast<int>(std::floor(p.y + half)));
                const int x0 = std::max(0, static_cast<int>(std::ceil(p.x - half)));
                const int x1 = std::min(width - 1, static_cast<int>(std::floor(p.x + half)));
                for (int y = y0; y <= y1; ++y)
                    for (int x = x0; x <= x1; ++x) {
                        float& nearest = zbuffer[static_cast<std::size_t>(y) * width + x];
                        nearest = std::min(nearest, p.z);
                    }
            });
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

namespace {

// The depth samples in the colour sensor's image, and the z-buffer they make there.
struct ColourView {
    std::vector<Projected> points;
    std::vector<float> zbuffer;
};

ColourView viewFromColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig, int colourWidth,
                          int colourHeight) {
    const frame::CameraModel depthCamera{rig.depth.intrinsics.scaledTo(depth.width, depth.height),
                                         rig.depth.lens};
    const frame::CameraModel colourCamera{rig.colour.intrinsics.scaledTo(colourWidth, colourHeight),
                                          rig.colour.lens};
    ColourView view;
    const double pixelsPerDepthPixel = std::max(colourCamera.intrinsics.fx / depthCamera.intrinsics.fx,
                                                colourCamera.intrinsics.fy / depthCamera.intrinsics.fy);
    // Samples just outside the image still cover its border pixels: twice a footprint is ample.
    const ColourTarget target{colourCamera, 2.0 * pixelsPerDepthPixel + 1.0, lensRadius2(colourCamera)};
    view.points = projectAll(depth, depthCamera, target, rig.depthToColour);
    view.zbuffer = nearestDepth(view.points, depth, pixelsPerDepthPixel, colourWidth, colourHeight);
    return view;
}

bool registrable(const frame::Plane<float>& depth, const frame::RigCalibration& rig, int colourWidth,
                 int colourHeight) {
    return !depth.empty() && colourWidth > 0 && colourHeight > 0 && rig.depth.intrinsics.valid() &&
           rig.colour.intrinsics.valid();
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
    parallelRanges(static_cast<int>(view.points.size()), 4096, [&](int begin, int end) {
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
            const Projected& p = view.points[i];
            if (!p.inside)
                continue;
            // Projections start at -0.5, so truncating x + 0.5 rounds to the nearest pixel.
            const auto x = std::min(static_cast<std::int32_t>(p.x + 0.5f), colourWidth - 1);
            const auto y = std::min(static_cast<std::int32_t>(p.y + 0.5f), colourHeight - 1);
            const std::int32_t pixel = y * colourWidth + x;
            if (p.z > view.zbuffer[static_cast<std::size_t>(pixel)] + sameSurfaceMeters(p.z))
                continue;
            out.colourPixel[i] = pixel;
            out.seen.pixels[i] = 1;
        }
    });
    return out;
}

frame::Plane<float> alignDepthToColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                                       int colourWidth, int colourHeight) {
    if (!registrable(depth, rig, colourWidth, colourHeight))
        return frame::Plane<float>(std::max(colourWidth, 0), std::max(colourHeight, 0));
    ColourView view = viewFromColour(depth, rig, colourWidth, colourHeight);
    frame::Plane<float> aligned;
    aligned.width = colourWidth;
    aligned.height = colourHeight;
    for (float& z : view.zbuffer)
        z = std::isfinite(z) ? z : 0.0f;
    aligned.pixels = std::move(view.zbuffer);
    return aligned;
}

bool isSingleCamera(const frame::RigCalibration& rig) {
    return rig.depthToColour.isIdentity() && rig.depth.lens == rig.colour.lens &&
           proportional(rig.depth.intrinsics, rig.colour.intrinsics);
}

PointColours framePointColours(const frame::Frame& frame, const frame::Plane<float>& depth,
                               CameraColourTable& table) {
    const frame::CapturedImage& image = frame.capturedImage;
    if (!frame.rig || isSingleCamera(*frame.rig))
        return {std::make_shared<const RgbImage>(pointColors(image, depth.width, depth.height, table)),
                nullptr};
    auto colours = std::make_shared<RgbImage>(
        RgbImage{depth.width, depth.height, std::vector<std::uint8_t>(depth.pixels.size() * 3, kUnseenGray)});
    const bool usable = table.use(image);
    Registration r = registerDepth(depth, *frame.rig, usable ? image.width : 0, usable ? image.height : 0);
    for (std::size_t i = 0; i < r.colourPixel.size(); ++i) {
        const std::int32_t pixel = r.colourPixel[i];
        if (pixel == Registration::kUnseen)
            continue;
        const std::uint32_t rgba = table.rgba(pixel % image.width, pixel / image.width);
        colours->pixels[i * 3] = static_cast<std::uint8_t>(rgba);
        colours->pixels[i * 3 + 1] = static_cast<std::uint8_t>(rgba >> 8);
        colours->pixels[i * 3 + 2] = static_cast<std::uint8_t>(rgba >> 16);
    }
    return {std::move(colours), std::make_shared<const frame::Plane<std::uint8_t>>(std::move(r.seen))};
}

RgbaImage seenColourOverlay(const PointColours& colours) {
    const RgbImage& rgb = *colours.colors;
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
    return *framePointColours(frame, nearest, table).colors;
}

} // namespace dc::processing
