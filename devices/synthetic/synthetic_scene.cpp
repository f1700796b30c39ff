#include "devices/synthetic/synthetic_scene.h"

#include "frame/camera_model.h"
#include "frame/color.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
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
constexpr double kPi = std::numbers::pi;
constexpr double kCameraPitchRadians = kCameraPitchDegrees * kPi / 180.0;
constexpr Vec3 kApple{kAppleCenter[0], kAppleCenter[1], kAppleCenter[2]};
constexpr double kHitEpsilon = 1e-6;

enum class Material : std::uint8_t { Sky, Desk, Floor, Wall, Blind, Apple, BookCover, BookPages };

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    Vec3 normal;
    Material material = Material::Sky;
};

struct Ray {
    Vec3 origin;
    Vec3 dir; // camera-z component 1, so the hit parameter t is the depth along the optical axis
};

// 1/d, or 0 for a ray parallel to the planes of that axis (which then never meets them).
double inverseOrZero(double d) {
    return std::abs(d) < 1e-12 ? 0.0 : 1.0 / d;
}

// The desk top (y = 0) and the floor: planes across y, met at t = (y - origin.y) / dir.y.
void hitHorizontal(const Ray& ray, double invY, Hit& best) {
    const double tDesk = -ray.origin.y * invY;
    if (tDesk > kHitEpsilon && tDesk < best.t) {
        const double x = ray.origin.x + ray.dir.x * tDesk, z = ray.origin.z + ray.dir.z * tDesk;
        if (std::abs(x) <= kDeskHalfWidth && z >= kDeskNear && z <= kDeskFar)
            best = {tDesk, {0, 1, 0}, Material::Desk};
    }
    const double tFloor = (kFloorY - ray.origin.y) * invY;
    if (tFloor > kHitEpsilon && tFloor < best.t && ray.origin.z + ray.dir.z * tFloor < kWallZ)
        best = {tFloor, {0, 1, 0}, Material::Floor};
}

bool inWindow(double x, double y) {
    return x > kWindowMinX && x < kWindowMaxX && y > kWindowBottom && y < kWindowTop;
}

// The back wall with its window opening, and the blinds just in front of the opening.
void hitWallAndBlinds(const Ray& ray, double invZ, Hit& best) {
    const double tWall = (kWallZ - ray.origin.z) * invZ;
    if (tWall > kHitEpsilon && tWall < best.t &&
        !inWindow(ray.origin.x + ray.dir.x * tWall, ray.origin.y + ray.dir.y * tWall))
        best = {tWall, {0, 0, -1}, Material::Wall};
    const double tBlinds = (kBlindsZ - ray.origin.z) * invZ;
    if (tBlinds <= kHitEpsilon || tBlinds >= best.t)
        return;
    const double x = ray.origin.x + ray.dir.x * tBlinds, y = ray.origin.y + ray.dir.y * tBlinds;
    const double above = y - kBlindsBottom;
    if (inWindow(x, y) && above > 0.0 && above - kSlatPitch * std::floor(above / kSlatPitch) < kSlatHeight)
        best = {tBlinds, {0, 0, -1}, Material::Blind};
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
    if (t <= kHitEpsilon || t >= best.t)
        return;
    best = {t, normalize(ray.origin + ray.dir * t - kApple), Material::Apple};
}

// The book, an axis-aligned box: the slab test finds the face the ray enters through (the last of the
// three slabs it enters), whose outward normal faces the ray.
void hitBook(const Ray& ray, Vec3 inv, Hit& best) {
    const double origin[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    const double dir[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    const double invDir[3] = {inv.x, inv.y, inv.z};
    double tNear = -std::numeric_limits<double>::infinity(), tFar = best.t;
    int entered = 0;
    for (int i = 0; i < 3; ++i) {
        if (invDir[i] == 0.0) {
            if (origin[i] < kBookMin[i] || origin[i] > kBookMax[i])
                return;
            continue;
        }
        double t0 = (kBookMin[i] - origin[i]) * invDir[i], t1 = (kBookMax[i] - origin[i]) * invDir[i];
        if (t0 > t1)
            std::swap(t0, t1);
        if (t0 > tNear) {
            tNear = t0;
            entered = i;
        }
        tFar = std::min(tFar, t1);
    }
    if (tNear > tFar || tNear <= kHitEpsilon || tNear >= best.t)
        return;
    const double outward = dir[entered] > 0.0 ? -1.0 : 1.0;
    const Vec3 normal{entered == 0 ? outward : 0.0, entered == 1 ? outward : 0.0,
                      entered == 2 ? outward : 0.0};
    best = {tNear, normal, entered == 1 ? Material::BookCover : Material::BookPages};
}

// Which of the small objects a ray may meet (false only where it surely misses them).
struct Candidates {
    bool apple = true;
    bool book = true;
};

Hit castRay(const Ray& ray, Candidates candidates = {}) {
    Hit best;
    const Vec3 inv{inverseOrZero(ray.dir.x), inverseOrZero(ray.dir.y), inverseOrZero(ray.dir.z)};
    hitHorizontal(ray, inv.y, best);
    hitWallAndBlinds(ray, inv.z, best);
    if (candidates.apple)
        hitSphere(ray, best);
    if (candidates.book)
        hitBook(ray, inv, best);
    return best;
}

struct CameraRays {
    Vec3 origin, right, down, forward;
    frame::Intrinsics k;
    frame::Lens lens;
    const std::array<double, 2>* directions = nullptr; // LensCamera's, when given

    Ray at(int u, int v) const {
        if (directions) {
            const auto [x, y] = directions[static_cast<std::size_t>(v) * k.width + u];
            return {origin, right * x + down * y + forward};
        }
        const double xn = (u - k.cx) / k.fx;
        const double yn = (v - k.cy) / k.fy;
        if (lens.model == frame::LensModel::None)
            return {origin, right * xn + down * yn + forward};
        const auto [x, y] = frame::undistortPoint(lens, xn, yn);
        return {origin, right * x + down * y + forward};
    }
};

CameraRays raysFor(const frame::CameraModel& camera, const frame::Pose& pose) {
    const auto& m = pose.cameraToWorld;
    return {{m[12], m[13], m[14]}, {m[0], m[1], m[2]}, {m[4], m[5], m[6]},
            {m[8], m[9], m[10]},   camera.intrinsics,  camera.lens};
}

CameraRays raysFor(const LensCamera& camera, const frame::Pose& pose) {
    CameraRays rays = raysFor(camera.camera, pose);
    if (!camera.directions.empty())
        rays.directions = camera.directions.data();
    return rays;
}

CameraRays raysFor(const frame::Intrinsics& k, const frame::Pose& pose) {
    return raysFor(frame::CameraModel{k, {}}, pose);
}

// The pixels whose rays can meet the box [lo, hi]: the rectangle around its corners' projections, a pixel
// wider (the projection of a convex box in front of the camera is the hull of its corners'). Every pixel
// when a corner is not in front of the camera.
struct PixelBox {
    double u0 = -1e300, v0 = -1e300, u1 = 1e300, v1 = 1e300;
    bool contains(int u, int v) const { return u >= u0 && u <= u1 && v >= v0 && v <= v1; }
};

PixelBox pixelsCovering(const CameraRays& rays, Vec3 lo, Vec3 hi) {
    // Through a lens the hull of the projected corners is no longer a bound: every pixel may meet it.
    if (rays.lens.model != frame::LensModel::None)
        return {};
    PixelBox box{1e300, 1e300, -1e300, -1e300};
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
        const Vec3 c = p - rays.origin;
        const double z = dot(c, rays.forward);
        if (z <= kHitEpsilon)
            return {};
        const double u = rays.k.fx * dot(c, rays.right) / z + rays.k.cx;
        const double v = rays.k.fy * dot(c, rays.down) / z + rays.k.cy;
        box = {std::min(box.u0, u - 1), std::min(box.v0, v - 1), std::max(box.u1, u + 1),
               std::max(box.v1, v + 1)};
    }
    return box;
}

// Casts the rays of every pixel, testing the apple and the book only where they can be seen.
struct SceneCaster {
    explicit SceneCaster(const CameraRays& r)
        : rays(r), apple(pixelsCovering(r, kApple - Vec3{kAppleRadius, kAppleRadius, kAppleRadius},
                                        kApple + Vec3{kAppleRadius, kAppleRadius, kAppleRadius})),
          book(pixelsCovering(r, {kBookMin[0], kBookMin[1], kBookMin[2]},
                              {kBookMax[0], kBookMax[1], kBookMax[2]})) {}

    Hit at(const Ray& ray, int u, int v) const {
        return castRay(ray, {apple.contains(u, v), book.contains(u, v)});
    }

    const CameraRays& rays;
    PixelBox apple, book;
};

std::vector<Hit> castAll(const frame::CameraModel& camera, const frame::Pose& pose) {
    const frame::Intrinsics& k = camera.intrinsics;
    const CameraRays rays = raysFor(camera, pose);
    const SceneCaster caster(rays);
    std::vector<Hit> hits(static_cast<std::size_t>(k.width) * k.height);
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u)
            hits[static_cast<std::size_t>(v) * k.width + u] = caster.at(rays.at(u, v), u, v);
    return hits;
}

float depthOf(const Hit& h) {
    return h.t <= SyntheticScene::kMaxRangeMeters ? static_cast<float>(h.t) : 0.0f;
}

// sin(x) to about 2e-4, plenty for a texture, without a libm call (the textures evaluate several per
// pixel): x reduced to [-pi/2, pi/2], then the Taylor series to x^7, whose error there is below
// (pi/2)^9 / 9!.
inline float fastSin(double x) {
    const auto turns = static_cast<std::int64_t>(x * (0.5 / kPi) + (x >= 0.0 ? 0.5 : -0.5));
    auto r = static_cast<float>(x - static_cast<double>(turns) * (2.0 * kPi));
    constexpr auto kHalfPi = static_cast<float>(0.5 * kPi);
    r = r > kHalfPi ? 2.0f * kHalfPi - r : (r < -kHalfPi ? -2.0f * kHalfPi - r : r);
    const float r2 = r * r;
    return r * (1.0f + r2 * (-1.0f / 6 + r2 * (1.0f / 120 + r2 * (-1.0f / 5040))));
}

// White noise in [0, 1) fixed to the world on a 1 mm grid: texture grain that stays put as the camera moves.
double grain(Vec3 p) {
    const auto cell = [](double v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(v * 1000.0 + 1e6));
    };
    std::uint64_t h = cell(p.x) * 0x9E3779B97F4A7C15ull ^ cell(p.y) * 0xC2B2AE3D27D4EB4Full ^
                      cell(p.z) * 0x165667B19E3779F9ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

frame::Rgb albedo(Material m, Vec3 p) {
    switch (m) {
    case Material::Sky:
        return {0.72f, 0.83f, 0.95f};
    case Material::Desk: {
        const float rings = 0.5f + 0.5f * fastSin(p.x * 70.0 + 4.0 * fastSin(p.z * 9.0));
        const auto g = static_cast<float>(0.85 + 0.15 * rings + 0.05 * grain(p));
        return {0.58f * g, 0.40f * g, 0.23f * g};
    }
    case Material::Floor: {
        const bool dark =
            (static_cast<int>(std::floor(p.x / 0.3)) + static_cast<int>(std::floor(p.z / 0.3))) & 1;
        return dark ? frame::Rgb{0.30f, 0.30f, 0.32f} : frame::Rgb{0.48f, 0.47f, 0.45f};
    }
    case Material::Wall: {
        const float s = 0.04f * fastSin(p.x * 12.0) * fastSin(p.y * 12.0);
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

const Vec3 kLight = normalize({0.4, 1.0, -0.5}); // from above, behind the camera's right shoulder

frame::Rgb shade(const Hit& hit, const Ray& ray) {
    const frame::Rgb a = albedo(hit.material, ray.origin + ray.dir * hit.t);
    if (hit.material == Material::Sky) {
        const auto up =
            static_cast<float>(std::clamp(ray.dir.y / std::sqrt(dot(ray.dir, ray.dir)), 0.0, 1.0));
        return {a.r - 0.2f * up, a.g - 0.1f * up, a.b};
    }
    const auto lambert = static_cast<float>(0.45 + 0.55 * std::max(0.0, dot(hit.normal, kLight)));
    return {a.r * lambert, a.g * lambert, a.b * lambert};
}

// frame::toByte's rounding, without its libm call: called three times per rendered pixel.
std::uint8_t byteOf(float normalised) {
    if (!(normalised > 0.0f))
        return 0;
    return static_cast<std::uint8_t>(std::min(normalised, 1.0f) * 255.0f + 0.5f);
}

} // namespace

frame::Intrinsics SyntheticScene::cameraIntrinsics(int width, int height) {
    const frame::Intrinsics full{1450.0, 1450.0, 960.0, 720.0, 1920, 1440};
    return full.scaledTo(width, height);
}

frame::Pose SyntheticScene::cameraPose(double timeSeconds, bool motion) {
    // Positive sway moves the camera to its right, which is world -x (the world's +x is on its left).
    const double sway = motion ? -0.15 * std::sin(2.0 * kPi * timeSeconds / 10.0) : 0.0;
    const Vec3 origin{sway, kCameraHeight, 0.0};
    // Turned about the vertical by yaw so the apple stays where it is in the image at rest.
    const double yaw = std::atan2(kApple.x - origin.x, kApple.z) - std::atan2(kApple.x, kApple.z);
    const double cp = std::cos(kCameraPitchRadians), sp = std::sin(kCameraPitchRadians);
    const Vec3 forward{std::sin(yaw) * cp, -sp, std::cos(yaw) * cp};
    const Vec3 right{-std::cos(yaw), 0.0, std::sin(yaw)}; // horizontal: forward x up, normalised
    const Vec3 down = cross(forward, right);              // right x down = forward: a rotation, det +1
    return {{right.x, right.y, right.z, 0, down.x, down.y, down.z, 0, forward.x, forward.y, forward.z, 0,
             origin.x, origin.y, origin.z, 1}};
}

frame::Plane<float> SyntheticScene::trueDepth(const frame::Intrinsics& k, const frame::Pose& pose) const {
    return trueDepth(frame::CameraModel{k, {}}, pose);
}

frame::Plane<float> SyntheticScene::trueDepth(const frame::CameraModel& camera,
                                              const frame::Pose& pose) const {
    const frame::Intrinsics& k = camera.intrinsics;
    const std::vector<Hit> hits = castAll(camera, pose);
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
    const std::vector<Hit> hits = castAll(frame::CameraModel{k, {}}, pose);
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

frame::DepthData flatTargetDepth(const frame::Intrinsics& k, const FlatTarget& target, bool noise,
                                 std::uint64_t seed, std::uint64_t sequence) {
    // The plane n.X = n.(0, 0, D) with n = (sin t, 0, cos t): along the ray (x', y', 1), z = D cos t / (n.r).
    const double t = target.tiltDegrees * std::numbers::pi / 180.0;
    const double nx = std::sin(t), nz = std::cos(t);
    std::seed_seq seq{seed, sequence};
    std::mt19937_64 rng(seq);
    std::normal_distribution<double> gauss(0.0, noise ? target.noiseMm * 1e-3 : 0.0);
    frame::DepthData out{frame::Plane<float>(k.width, k.height),
                         frame::Plane<std::uint8_t>(k.width, k.height, 0)};
    for (int y = 0; y < k.height; ++y) {
        for (int x = 0; x < k.width; ++x) {
            const double along = nx * (x - k.cx) / k.fx + nz;
            const double z = along > 0.0 ? target.distanceMeters * nz / along : -1.0;
            if (!(z > 0.0) || z > SyntheticScene::kMaxRangeMeters)
                continue;
            out.depthMeters.at(x, y) = static_cast<float>(std::max(1e-3, z + gauss(rng)));
            out.confidence.at(x, y) = static_cast<std::uint8_t>(frame::Confidence::High);
        }
    }
    return out;
}

frame::CapturedImage SyntheticScene::renderImage(const frame::Intrinsics& k, const frame::Pose& pose) const {
    return renderImage(frame::CameraModel{k, {}}, pose);
}

LensCamera lensCamera(const frame::CameraModel& camera) {
    LensCamera out{camera, {}};
    if (camera.lens.model == frame::LensModel::None)
        return out;
    const frame::Intrinsics& k = camera.intrinsics;
    out.directions.reserve(static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height));
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u)
            out.directions.push_back(
                frame::undistortPoint(camera.lens, (u - k.cx) / k.fx, (v - k.cy) / k.fy));
    return out;
}

frame::CapturedImage SyntheticScene::renderImage(const frame::CameraModel& camera,
                                                 const frame::Pose& pose) const {
    return renderImage(lensCamera(camera), pose);
}

frame::CapturedImage SyntheticScene::renderImage(const LensCamera& camera, const frame::Pose& pose) const {
    const frame::Intrinsics& k = camera.camera.intrinsics;
    const CameraRays rays = raysFor(camera, pose);
    const SceneCaster caster(rays);
    const int w = k.width, h = k.height;
    const int cw = (w + 1) / 2;
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(
        frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, w, h));
    std::uint8_t* chroma = bytes->data() + static_cast<std::size_t>(w) * h;
    // Chroma is the mean over each 2x2 block, so rows are rendered in pairs.
    std::vector<float> cb(static_cast<std::size_t>(cw)), cr(cb.size());
    std::vector<int> count(cb.size());
    for (int v0 = 0; v0 < h; v0 += 2) {
        std::fill(cb.begin(), cb.end(), 0.0f);
        std::fill(cr.begin(), cr.end(), 0.0f);
        std::fill(count.begin(), count.end(), 0);
        for (int v = v0; v < std::min(v0 + 2, h); ++v) {
            std::uint8_t* luma = bytes->data() + static_cast<std::size_t>(v) * w;
            for (int u = 0; u < w; ++u) {
                const Ray ray = rays.at(u, v);
                const frame::Ycbcr c = frame::rgbToYcbcr(shade(caster.at(ray, u, v), ray));
                luma[u] = byteOf(c.y);
                cb[u / 2] += c.cb;
                cr[u / 2] += c.cr;
                ++count[u / 2];
            }
        }
        std::uint8_t* row = chroma + static_cast<std::size_t>(v0 / 2) * 2 * cw;
        for (int i = 0; i < cw; ++i) {
            row[2 * i] = byteOf(cb[i] / static_cast<float>(count[i]));
            row[2 * i + 1] = byteOf(cr[i] / static_cast<float>(count[i]));
        }
    }
    return {frame::PixelFormat::Nv12, w, h, std::move(bytes)};
}

namespace {

// A rotation by `yDegrees` about the camera's y axis after `xDegrees` about its x axis, row-major.
std::array<double, 9> smallRotation(double xDegrees, double yDegrees) {
    const double a = xDegrees * kPi / 180.0, b = yDegrees * kPi / 180.0;
    const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
    // Ry(b) * Rx(a)
    return {cb, sb * sa, sb * ca, 0.0, ca, -sa, -sb, cb * sa, cb * ca};
}

Vec3 inCameraAxes(const CameraRays& rays, Vec3 p) {
    const Vec3 c = p - rays.origin;
    return {dot(c, rays.right), dot(c, rays.down), dot(c, rays.forward)};
}

} // namespace

frame::RigCalibration syntheticRigCalibration() {
    frame::RigCalibration rig;
    rig.depth.intrinsics = {446.0, 446.0, 423.5, 239.5, 848, 480};
    rig.colour.intrinsics = {931.5, 931.5, 639.5, 359.5, 1280, 720};
    rig.colour.lens = {frame::LensModel::BrownConrady, {0.1, -0.2, 0.0008, -0.0005, 0.08}};
    rig.depthToColour.rotation = smallRotation(-0.2, 0.4);
    // The colour sensor's centre sits at c = (15 mm, 0, 0) in the depth sensor's frame: t = -R c.
    const auto& r = rig.depthToColour.rotation;
    constexpr double kBaselineMeters = 0.015;
    rig.depthToColour.translationMeters = {-r[0] * kBaselineMeters, -r[3] * kBaselineMeters,
                                           -r[6] * kBaselineMeters};
    rig.name = "synthetic rig (exact)";
    return rig;
}

frame::Pose colourSensorPose(const frame::Pose& depthPose, const frame::RigidTransform& depthToColour) {
    const auto& m = depthPose.cameraToWorld;
    const Vec3 right{m[0], m[1], m[2]}, down{m[4], m[5], m[6]}, forward{m[8], m[9], m[10]};
    const auto inWorld = [&](Vec3 a) { return right * a.x + down * a.y + forward * a.z; };
    const auto& r = depthToColour.rotation;
    const auto& t = depthToColour.translationMeters;
    // The colour sensor's axes are the rows of R in depth coordinates; its centre is -Rᵀ t.
    const Vec3 x = inWorld({r[0], r[1], r[2]}), y = inWorld({r[3], r[4], r[5]}),
               z = inWorld({r[6], r[7], r[8]});
    const Vec3 centre{-(r[0] * t[0] + r[3] * t[1] + r[6] * t[2]), -(r[1] * t[0] + r[4] * t[1] + r[7] * t[2]),
                      -(r[2] * t[0] + r[5] * t[1] + r[8] * t[2])};
    const Vec3 o = Vec3{m[12], m[13], m[14]} + inWorld(centre);
    return {{x.x, x.y, x.z, 0, y.x, y.y, y.z, 0, z.x, z.y, z.z, 0, o.x, o.y, o.z, 1}};
}

RegistrationTruth SyntheticScene::registrationTruth(const frame::CameraModel& depthCamera,
                                                    const frame::CameraModel& colourCamera,
                                                    const frame::RigidTransform& depthToColour,
                                                    const frame::Pose& depthPose) const {
    const frame::Intrinsics& k = depthCamera.intrinsics;
    const CameraRays depthRays = raysFor(depthCamera, depthPose);
    const CameraRays colourRays = raysFor(colourCamera, colourSensorPose(depthPose, depthToColour));
    const frame::Intrinsics& kc = colourCamera.intrinsics;
    RegistrationTruth truth{std::vector<std::array<double, 2>>(static_cast<std::size_t>(k.width) * k.height,
                                                               {std::nan(""), std::nan("")}),
                            std::vector<std::uint8_t>(static_cast<std::size_t>(k.width) * k.height)};
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u) {
            const Ray ray = depthRays.at(u, v);
            const Hit hit = castRay(ray);
            if (hit.t > kMaxRangeMeters)
                continue;
            const Vec3 p = inCameraAxes(colourRays, ray.origin + ray.dir * hit.t);
            const auto pixel = frame::projectPoint(colourCamera, {p.x, p.y, p.z});
            if (!pixel)
                continue;
            const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
            truth.colourPixel[i] = *pixel;
            const bool inside = (*pixel)[0] >= -0.5 && (*pixel)[1] >= -0.5 && (*pixel)[0] < kc.width - 0.5 &&
                                (*pixel)[1] < kc.height - 0.5;
            // The colour camera's own ray to the point, scaled like every ray here to unit camera z: the
            // point is seen when nothing is met before it.
            const Vec3 toPoint = ray.origin + ray.dir * hit.t - colourRays.origin;
            const Hit first = castRay({colourRays.origin, toPoint * (1.0 / p.z)});
            truth.visible[i] = inside && first.t >= p.z * (1.0 - 1e-9) - 1e-9;
        }
    return truth;
}

} // namespace dc::devices
