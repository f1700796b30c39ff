#include "devices/synthetic/synthetic_scene.h"

#include "frame/color.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace dc::devices {

namespace {

struct Vec3 {
    double x = 0, y = 0, z = 0;
};
Vec3 operator+(Vec3 a, Vec3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
Vec3 operator-(Vec3 a, Vec3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec3 operator*(Vec3 a, double s) {
    return {a.x * s, a.y * s, a.z * s};
}
double dot(Vec3 a, Vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 normalize(Vec3 a) {
    return a * (1.0 / std::sqrt(dot(a, a)));
}

using namespace scene;
constexpr double kCameraPitchRadians = kCameraPitchDegrees * 3.14159265358979323846 / 180.0;
constexpr Vec3 kApple{kAppleCenter[0], kAppleCenter[1], kAppleCenter[2]};
constexpr Vec3 kBookLow{kBookMin[0], kBookMin[1], kBookMin[2]};
constexpr Vec3 kBookHigh{kBookMax[0], kBookMax[1], kBookMax[2]};

enum class Material { Sky, Desk, Floor, Wall, Blind, Apple, BookCover, BookPages };

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    Vec3 normal;
    Material material = Material::Sky;
};

struct Ray {
    Vec3 origin;
    Vec3 dir; // camera-z component 1, so the hit parameter t is the depth along the optical axis
};

double axis(Vec3 v, int i) {
    return i == 0 ? v.x : (i == 1 ? v.y : v.z);
}

// Intersects the axis-aligned plane coordinate[axisIndex] == value; `inside` limits the plane's extent.
template <class Inside>
void hitPlane(const Ray& ray, int axisIndex, double value, Vec3 normal, Material m, Hit& best,
              Inside inside) {
    const double d = axis(ray.dir, axisIndex);
    if (std::abs(d) < 1e-12)
        return;
    const double t = (value - axis(ray.origin, axisIndex)) / d;
    if (t <= 1e-6 || t >= best.t)
        return;
    const Vec3 p = ray.origin + ray.dir * t;
    if (inside(p))
        best = {t, normal, m};
}

void hitSphere(const Ray& ray, Hit& best) {
    const Vec3 oc = ray.origin - kApple;
    const double a = dot(ray.dir, ray.dir);
    const double b = dot(oc, ray.dir);
    const double c = dot(oc, oc) - kAppleRadius * kAppleRadius;
    const double disc = b * b - a * c;
    if (disc < 0)
        return;
    const double t = (-b - std::sqrt(disc)) / a;
    if (t <= 1e-6 || t >= best.t)
        return;
    best = {t, normalize(ray.origin + ray.dir * t - kApple), Material::Apple};
}

void hitBook(const Ray& ray, Hit& best) {
    for (int i = 0; i < 3; ++i) {
        for (int side = 0; side < 2; ++side) {
            const double value = axis(side ? kBookHigh : kBookLow, i);
            Vec3 n{i == 0 ? 1.0 : 0.0, i == 1 ? 1.0 : 0.0, i == 2 ? 1.0 : 0.0};
            n = n * (side ? 1.0 : -1.0);
            const Material m = i == 1 ? Material::BookCover : Material::BookPages;
            hitPlane(ray, i, value, n, m, best, [&](Vec3 p) {
                for (int j = 0; j < 3; ++j)
                    if (j != i && (axis(p, j) < axis(kBookLow, j) || axis(p, j) > axis(kBookHigh, j)))
                        return false;
                return true;
            });
        }
    }
}

Hit castRay(const Ray& ray) {
    Hit best;
    hitPlane(ray, 1, 0.0, {0, 1, 0}, Material::Desk, best,
             [](Vec3 p) { return std::abs(p.x) <= kDeskHalfWidth && p.z >= kDeskNear && p.z <= kDeskFar; });
    hitPlane(ray, 1, kFloorY, {0, 1, 0}, Material::Floor, best, [](Vec3 p) { return p.z < kWallZ; });
    const auto inWindow = [](Vec3 p) {
        return p.x > kWindowLeft && p.x < kWindowRight && p.y > kWindowBottom && p.y < kWindowTop;
    };
    hitPlane(ray, 2, kWallZ, {0, 0, -1}, Material::Wall, best, [&](Vec3 p) { return !inWindow(p); });
    hitPlane(ray, 2, kBlindsZ, {0, 0, -1}, Material::Blind, best, [&](Vec3 p) {
        return inWindow(p) && p.y > kBlindsBottom && std::fmod(p.y - kBlindsBottom, kSlatPitch) < kSlatHeight;
    });
    hitSphere(ray, best);
    hitBook(ray, best);
    return best;
}

struct CameraRays {
    Vec3 origin, right, down, forward;
    const frame::Intrinsics& k;

    Ray at(int u, int v) const {
        const double xn = (u - k.cx) / k.fx;
        const double yn = (v - k.cy) / k.fy;
        return {origin, right * xn + down * yn + forward};
    }
};

CameraRays raysFor(const frame::Intrinsics& k, const frame::Pose& pose) {
    const auto& m = pose.cameraToWorld;
    return {{m[12], m[13], m[14]}, {m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}, k};
}

std::vector<Hit> castAll(const frame::Intrinsics& k, const frame::Pose& pose) {
    const CameraRays rays = raysFor(k, pose);
    std::vector<Hit> hits(static_cast<std::size_t>(k.width) * k.height);
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u)
            hits[static_cast<std::size_t>(v) * k.width + u] = castRay(rays.at(u, v));
    return hits;
}

float depthOf(const Hit& h) {
    return h.t <= SyntheticScene::kMaxRangeMeters ? static_cast<float>(h.t) : 0.0f;
}

// Cheap deterministic per-position value noise in [0, 1) for texture grain.
double hash3(Vec3 p) {
    const double s = std::sin(p.x * 127.1 + p.y * 311.7 + p.z * 74.7) * 43758.5453;
    return s - std::floor(s);
}

frame::Rgb albedo(Material m, Vec3 p) {
    switch (m) {
    case Material::Sky:
        return {0.72f, 0.83f, 0.95f};
    case Material::Desk: {
        const double grain = 0.5 + 0.5 * std::sin(p.x * 70.0 + 4.0 * std::sin(p.z * 9.0));
        const auto g = static_cast<float>(0.85 + 0.15 * grain + 0.05 * hash3(p * 50.0));
        return {0.58f * g, 0.40f * g, 0.23f * g};
    }
    case Material::Floor: {
        const bool dark =
            (static_cast<int>(std::floor(p.x / 0.3)) + static_cast<int>(std::floor(p.z / 0.3))) & 1;
        return dark ? frame::Rgb{0.30f, 0.30f, 0.32f} : frame::Rgb{0.48f, 0.47f, 0.45f};
    }
    case Material::Wall: {
        const auto s = static_cast<float>(0.04 * std::sin(p.x * 12.0) * std::sin(p.y * 12.0));
        return {0.84f + s, 0.81f + s, 0.74f + s};
    }
    case Material::Blind:
        return {0.93f, 0.93f, 0.91f};
    case Material::Apple: {
        const auto top = static_cast<float>(std::clamp((p.y - kApple.y) / kAppleRadius, 0.0, 1.0));
        return {0.80f - 0.2f * top, 0.08f + 0.45f * top, 0.06f};
    }
    case Material::BookCover:
        return {0.12f, 0.18f, 0.45f};
    case Material::BookPages:
        return {0.92f, 0.89f, 0.80f};
    }
    return {};
}

frame::Rgb shade(const Hit& hit, const Ray& ray) {
    const Vec3 p = ray.origin + ray.dir * hit.t;
    const frame::Rgb a = albedo(hit.material, p);
    if (hit.material == Material::Sky) {
        const auto up = static_cast<float>(std::clamp(normalize(ray.dir).y, 0.0, 1.0));
        return {a.r - 0.2f * up, a.g - 0.1f * up, a.b};
    }
    static const Vec3 kLight = normalize({-0.4, 1.0, -0.5});
    const auto lambert = static_cast<float>(0.45 + 0.55 * std::max(0.0, dot(hit.normal, kLight)));
    return {a.r * lambert, a.g * lambert, a.b * lambert};
}

} // namespace

frame::Intrinsics SyntheticScene::cameraIntrinsics(int width, int height) {
    const frame::Intrinsics full{1450.0, 1450.0, 960.0, 720.0, 1920, 1440};
    return full.scaledTo(width, height);
}

frame::Pose SyntheticScene::cameraPose(double timeSeconds, bool motion) {
    const double sway = motion ? 0.15 * std::sin(2.0 * 3.14159265358979323846 * timeSeconds / 10.0) : 0.0;
    const Vec3 origin{sway, kCameraHeight, 0.0};
    const double yaw = std::atan2(kApple.x - origin.x, kApple.z) - std::atan2(kApple.x, kApple.z);
    const double cp = std::cos(kCameraPitchRadians), sp = std::sin(kCameraPitchRadians);
    const Vec3 forward{std::sin(yaw) * cp, -sp, std::cos(yaw) * cp};
    const Vec3 right{std::cos(yaw), 0.0, -std::sin(yaw)};
    const Vec3 down = cross(right, forward);
    return {{right.x, right.y, right.z, 0, down.x, down.y, down.z, 0, forward.x, forward.y, forward.z, 0,
             origin.x, origin.y, origin.z, 1}};
}

frame::Plane<float> SyntheticScene::trueDepth(const frame::Intrinsics& k, const frame::Pose& pose) const {
    const std::vector<Hit> hits = castAll(k, pose);
    frame::Plane<float> depth(k.width, k.height);
    for (std::size_t i = 0; i < hits.size(); ++i)
        depth.pixels[i] = depthOf(hits[i]);
    return depth;
}

namespace {

// Relative depth jump to a 4-neighbour beyond which a pixel straddles an edge, where a real time-of-flight
// sensor mixes foreground and background returns ("flying pixels").
constexpr float kEdgeJump = 0.03f;

// The neighbour across a depth edge (0 for a neighbour without return), or a negative value if none.
float edgeNeighbour(const frame::Plane<float>& truth, int x, int y) {
    const float z = truth.at(x, y);
    float across = -1.0f;
    float worst = kEdgeJump;
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int i = 0; i < 4; ++i) {
        const int nx = x + dx[i], ny = y + dy[i];
        if (nx < 0 || ny < 0 || nx >= truth.width || ny >= truth.height)
            continue;
        const float n = truth.at(nx, ny);
        const float jump = n > 0.0f ? std::abs(n - z) / z : 1.0f;
        if (jump > worst) {
            worst = jump;
            across = n;
        }
    }
    return across;
}

// Standard deviation (meters) of a LiDAR-like measurement: a floor plus quadratic growth with distance,
// inflated at grazing incidence where the footprint smears over a range of depths.
double noiseSigmaMeters(double z, double cosIncidence) {
    return (0.001 + 0.0015 * z * z) / std::max(cosIncidence, 0.25);
}

frame::Confidence confidenceFor(double sigmaMeters) {
    if (sigmaMeters < 0.004)
        return frame::Confidence::High;
    return sigmaMeters < 0.010 ? frame::Confidence::Medium : frame::Confidence::Low;
}

} // namespace

frame::DepthData SyntheticScene::sensorDepth(const frame::Intrinsics& k, const frame::Pose& pose,
                                             std::uint64_t sequence) const {
    const CameraRays rays = raysFor(k, pose);
    const std::vector<Hit> hits = castAll(k, pose);
    frame::Plane<float> truth(k.width, k.height);
    for (std::size_t i = 0; i < hits.size(); ++i)
        truth.pixels[i] = depthOf(hits[i]);

    std::seed_seq seq{seed_, sequence};
    std::mt19937_64 rng(seq);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);

    frame::DepthData out{frame::Plane<float>(k.width, k.height),
                         frame::Plane<std::uint8_t>(k.width, k.height, 0)};
    for (int y = 0; y < k.height; ++y) {
        for (int x = 0; x < k.width; ++x) {
            const float z = truth.at(x, y);
            if (z <= 0.0f)
                continue;
            const float across = edgeNeighbour(truth, x, y);
            if (across >= 0.0f) {
                // A mixed return somewhere between the two surfaces (or none, half of the time, when the
                // other side is out of range); never trusted.
                const float w = uniform(rng);
                out.depthMeters.at(x, y) =
                    across > 0.0f ? z + (across - z) * 0.5f * w : (w < 0.5f ? 0.0f : z);
                continue;
            }
            const Hit& hit = hits[static_cast<std::size_t>(y) * k.width + x];
            const double cosInc = std::abs(dot(hit.normal, normalize(rays.at(x, y).dir)));
            const double sigma = noiseSigmaMeters(z, cosInc);
            out.depthMeters.at(x, y) = static_cast<float>(std::max(1e-3, z + sigma * gauss(rng)));
            out.confidence.at(x, y) = static_cast<std::uint8_t>(confidenceFor(sigma));
        }
    }
    return out;
}

frame::CapturedImage SyntheticScene::renderImage(const frame::Intrinsics& k, const frame::Pose& pose) const {
    const CameraRays rays = raysFor(k, pose);
    const int w = k.width, h = k.height;
    const int cw = (w + 1) / 2, ch = (h + 1) / 2;
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(
        frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, w, h));
    std::vector<float> cb(static_cast<std::size_t>(cw) * ch), cr(cb.size());
    std::vector<int> count(cb.size());
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const Ray ray = rays.at(u, v);
            const frame::Ycbcr c = frame::rgbToYcbcr(shade(castRay(ray), ray));
            (*bytes)[static_cast<std::size_t>(v) * w + u] = frame::toByte(c.y);
            const std::size_t ci = static_cast<std::size_t>(v / 2) * cw + u / 2;
            cb[ci] += c.cb;
            cr[ci] += c.cr;
            ++count[ci];
        }
    }
    std::uint8_t* chroma = bytes->data() + static_cast<std::size_t>(w) * h;
    for (std::size_t i = 0; i < cb.size(); ++i) {
        chroma[2 * i] = frame::toByte(cb[i] / static_cast<float>(count[i]));
        chroma[2 * i + 1] = frame::toByte(cr[i] / static_cast<float>(count[i]));
    }
    return {frame::PixelFormat::Nv12, w, h, std::move(bytes)};
}

} // namespace dc::devices
