#include "processing/rigid_alignment.h"

#include "processing/depth_quality.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

namespace dc::processing {

namespace {

using Vec3 = std::array<double, 3>;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// 1.4826 x the median |residual| estimates sigma for Gaussian noise; Tukey's biweight reaches zero at 4.685
// sigma, which keeps 95 % efficiency on Gaussian residuals.
constexpr double kMadToSigma = 1.4826;
constexpr double kTukeyWidth = 4.685;
// The biweight's width never falls below this, so a noise-free pair of clouds (median residual 0) keeps its
// points.
constexpr double kMinTukeyMeters = 1e-4;
// A seed rotation farther than this from orthonormal is not a rotation (the caller's bug, or a corrupt file).
constexpr double kMaxSeedRotationError = 1e-3;

Vec3 operator-(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) {
    return std::sqrt(dot(a, a));
}

bool validDepth(float z) {
    return std::isfinite(z) && z > 0.0f;
}

// A point of A moved into B's frame, the B sample it projects to, B's unit normal there (facing B's camera),
// and the signed point-to-plane distance n . (p - q).
struct Pair {
    Vec3 p;
    Vec3 q;
    Vec3 n;
    double residual = 0.0;
};

// B's depth map as a surface to pair points with. Normals are fitted where a pair first needs one and kept:
// successive iterations land on mostly the same pixels.
class Surface {
public:
    Surface(const DepthCloud& cloud, const AssociationParams& params)
        : depth_(cloud.depth->depthMeters), k_(cloud.intrinsics), span_(std::max(1, params.normalSpanPixels)),
          maxJump_(params.maxDepthJumpPerPixel), normals_(depth_.pixels.size()),
          known_(depth_.pixels.size(), kUnknown) {}

    std::optional<Pair> pair(const Vec3& p, double maxDistanceMeters) {
        if (!(p[2] > 0.0))
            return std::nullopt;
        // Nearest pixel; the range is checked in double so that a far-off projection never overflows an int.
        const double u = std::floor(k_.fx * p[0] / p[2] + k_.cx + 0.5);
        const double v = std::floor(k_.fy * p[1] / p[2] + k_.cy + 0.5);
        if (!(u >= 0.0 && v >= 0.0 && u < depth_.width && v < depth_.height))
            return std::nullopt;
        const int x = static_cast<int>(u), y = static_cast<int>(v);
        if (!validDepth(depth_.at(x, y)))
            return std::nullopt;
        const Vec3 q = pointAt(x, y);
        if (norm(p - q) > maxDistanceMeters)
            return std::nullopt;
        const std::size_t i = static_cast<std::size_t>(y) * depth_.width + x;
        if (known_[i] == kUnknown) {
            const std::optional<Vec3> n = fitNormal(x, y, q);
            known_[i] = n ? kHasNormal : kNoNormal;
            if (n)
                normals_[i] = *n;
        }
        if (known_[i] == kNoNormal)
            return std::nullopt;
        return Pair{p, q, normals_[i], dot(normals_[i], p - q)};
    }

private:
    static constexpr std::uint8_t kUnknown = 0, kNoNormal = 1, kHasNormal = 2;

    Vec3 pointAt(int x, int y) const {
        const double z = depth_.at(x, y);
        return {(x - k_.cx) * z / k_.fx, (y - k_.cy) * z / k_.fy, z};
    }

    // The plane P(du, dv) = P0 + du Tu + dv Tv fitted by least squares to the samples of the window of
    // half-side span_ that lie on the centre's surface; the normal is Tu x Tv, facing the camera. A window's
    // fit averages the depth noise over all its samples: the cross product of two single differences is so
    // noisy on a plane that it makes the plane look as if it constrained motion along itself. None where
    // less than half the window is on the surface.
    std::optional<Vec3> fitNormal(int x, int y, const Vec3& q) const {
        const int s = span_;
        if (x < s || y < s || x + s >= depth_.width || y + s >= depth_.height)
            return std::nullopt;
        const float centre = depth_.at(x, y);
        double count = 0.0, su = 0.0, sv = 0.0, suu = 0.0, svv = 0.0, suv = 0.0;
        Vec3 sp{}, sup{}, svp{};
        for (int dv = -s; dv <= s; ++dv)
            for (int du = -s; du <= s; ++du) {
                const float z = depth_.at(x + du, y + dv);
                if (!validDepth(z) ||
                    std::abs(z - centre) > maxJump_ * std::max(std::abs(du), std::abs(dv)) * centre)
                    continue;
                const Vec3 p = pointAt(x + du, y + dv);
                count += 1.0;
                su += du, sv += dv, suu += du * du, svv += dv * dv, suv += du * dv;
                for (int j = 0; j < 3; ++j)
                    sp[j] += p[j], sup[j] += du * p[j], svp[j] += dv * p[j];
            }
        if (2.0 * count < (2.0 * s + 1.0) * (2.0 * s + 1.0))
            return std::nullopt;
        // Centred sums, then the 2x2 normal equations of (Tu, Tv) for each coordinate.
        const double cuu = suu - su * su / count, cvv = svv - sv * sv / count, cuv = suv - su * sv / count;
        const double det = cuu * cvv - cuv * cuv;
        if (!(det > 0.0))
            return std::nullopt;
        Vec3 tu{}, tv{};
        for (int j = 0; j < 3; ++j) {
            const double cup = sup[j] - su * sp[j] / count, cvp = svp[j] - sv * sp[j] / count;
            tu[j] = (cvv * cup - cuv * cvp) / det;
            tv[j] = (cuu * cvp - cuv * cup) / det;
        }
        const Vec3 n = cross(tu, tv);
        const double length = norm(n);
        if (!(length > 0.0))
            return std::nullopt;
        const double sign = dot(n, q) > 0.0 ? -1.0 : 1.0;
        return Vec3{sign * n[0] / length, sign * n[1] / length, sign * n[2] / length};
    }

    const frame::Plane<float>& depth_;
    frame::Intrinsics k_;
    int span_;
    double maxJump_;
    std::vector<Vec3> normals_;
    std::vector<std::uint8_t> known_;
};

// A's valid samples, every stride-th in each direction, in A's frame.
std::vector<Vec3> samplePoints(const DepthCloud& a, int stride) {
    const frame::Plane<float>& depth = a.depth->depthMeters;
    const frame::Intrinsics& k = a.intrinsics;
    const int step = std::max(1, stride);
    std::vector<Vec3> points;
    points.reserve(static_cast<std::size_t>(depth.width / step + 1) * (depth.height / step + 1));
    for (int y = 0; y < depth.height; y += step)
        for (int x = 0; x < depth.width; x += step) {
            const float z = depth.at(x, y);
            if (validDepth(z))
                points.push_back({(x - k.cx) * z / k.fx, (y - k.cy) * z / k.fy, z});
        }
    return points;
}

std::vector<Pair> associate(const std::vector<Vec3>& points, const frame::RigidTransform& aToB,
                            Surface& surface, double maxDistanceMeters) {
    std::vector<Pair> pairs;
    pairs.reserve(points.size());
    for (const Vec3& p : points)
        if (const std::optional<Pair> pair = surface.pair(aToB.apply(p), maxDistanceMeters))
            pairs.push_back(*pair);
    return pairs;
}

double medianAbsResidual(const std::vector<Pair>& pairs) {
    if (pairs.empty())
        return 0.0;
    std::vector<double> magnitudes(pairs.size());
    std::transform(pairs.begin(), pairs.end(), magnitudes.begin(),
                   [](const Pair& pair) { return std::abs(pair.residual); });
    const auto middle = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
    std::nth_element(magnitudes.begin(), middle, magnitudes.end());
    return *middle;
}

OverlapFigure figureOf(const std::vector<Pair>& pairs, std::size_t candidates) {
    OverlapFigure figure;
    figure.count = pairs.size();
    figure.candidates = candidates;
    figure.medianMm = medianAbsResidual(pairs) * kMetersToMm;
    figure.overlapFraction = candidates > 0 ? static_cast<double>(pairs.size()) / candidates : 0.0;
    return figure;
}

using Rotation = std::array<double, 9>;

// Rodrigues' formula: the rotation by |w| radians about w.
Rotation exponential(const Vec3& w) {
    const double angle = norm(w);
    if (angle < 1e-12)
        return {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const Vec3 a{w[0] / angle, w[1] / angle, w[2] / angle};
    const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
    return {t * a[0] * a[0] + c,        t * a[0] * a[1] - s * a[2], t * a[0] * a[2] + s * a[1],
            t * a[0] * a[1] + s * a[2], t * a[1] * a[1] + c,        t * a[1] * a[2] - s * a[0],
            t * a[0] * a[2] - s * a[1], t * a[1] * a[2] + s * a[0], t * a[2] * a[2] + c};
}

// The nearest rotation (polar decomposition through the SVD): products of many small updates drift off
// orthonormal by rounding, and a matrix that is not quite a rotation would shear the cloud.
Rotation orthonormalised(const Rotation& r) {
    const cv::Matx33d m(r.data());
    cv::Matx33d u, vt;
    cv::Matx31d w;
    cv::SVD::compute(m, w, u, vt);
    if (cv::determinant(u * vt) < 0.0)
        for (int i = 0; i < 3; ++i)
            u(i, 2) = -u(i, 2);
    const cv::Matx33d out = u * vt;
    return {out(0, 0), out(0, 1), out(0, 2), out(1, 0), out(1, 1),
            out(1, 2), out(2, 0), out(2, 1), out(2, 2)};
}

// Tukey's biweight of each residual, its width from the residuals' median absolute value.
std::vector<double> tukeyWeights(const std::vector<Pair>& pairs) {
    const double width = std::max(kMinTukeyMeters, kTukeyWidth * kMadToSigma * medianAbsResidual(pairs));
    std::vector<double> weights(pairs.size());
    std::transform(pairs.begin(), pairs.end(), weights.begin(), [width](const Pair& pair) {
        const double u = pair.residual / width;
        return std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    });
    return weights;
}

// One Gauss-Newton step: the small rotation w (radians) and translation t (meters) that, applied after the
// current transform as p -> p + w x p + t, best cancel the weighted residuals.
struct Step {
    Vec3 rotation{};
    Vec3 translation{};
    double conditionRatio = 0.0;
    int constrainedDirections = 0;
};

// The weighted normal equations H x = g of the residuals' linearisation. The rotation is taken about the
// points' centroid c and scaled by their RMS radius, so that all six unknowns are lengths and H's eigenvalues
// compare one motion's constraint with another's whatever the cloud's distance from the camera; the
// unknowns are (radius * w, t + w x c).
struct NormalEquations {
    cv::Matx66d h = cv::Matx66d::zeros();
    cv::Vec6d g;
    Vec3 centroid{};
    double radius = 1.0;
};

NormalEquations normalEquations(const std::vector<Pair>& pairs, const std::vector<double>& weights) {
    NormalEquations eq;
    double total = 0.0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        total += weights[i];
        for (int j = 0; j < 3; ++j)
            eq.centroid[j] += weights[i] * pairs[i].p[j];
    }
    for (double& c : eq.centroid)
        c /= total;
    double spread = 0.0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const Vec3 d = pairs[i].p - eq.centroid;
        spread += weights[i] * dot(d, d);
    }
    eq.radius = std::max(1e-3, std::sqrt(spread / total));
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        if (weights[i] == 0.0)
            continue;
        const Vec3& n = pairs[i].n;
        const Vec3 arm = cross(pairs[i].p - eq.centroid, n);
        const cv::Vec6d row(arm[0] / eq.radius, arm[1] / eq.radius, arm[2] / eq.radius, n[0], n[1], n[2]);
        eq.h += weights[i] * row * row.t();
        eq.g += -weights[i] * pairs[i].residual * row;
    }
    return eq;
}

// Solves in H's eigenbasis and drops the directions whose eigenvalue is below minConditionRatio of the
// largest: along those the residuals barely change, so noise alone would move the transform there.
Step solve(const std::vector<Pair>& pairs, const std::vector<double>& weights, double minConditionRatio) {
    const NormalEquations eq = normalEquations(pairs, weights);
    cv::Vec6d values;
    cv::Matx66d vectors; // rows, by decreasing eigenvalue
    cv::eigen(eq.h, values, vectors);
    Step step;
    if (!(values[0] > 0.0))
        return step;
    step.conditionRatio = std::max(0.0, values[5]) / values[0];
    cv::Vec6d x;
    for (int i = 0; i < 6; ++i) {
        if (values[i] < minConditionRatio * values[0])
            continue;
        ++step.constrainedDirections;
        const cv::Vec6d direction(vectors.row(i).val);
        x += direction * (direction.dot(eq.g) / values[i]);
    }
    step.rotation = {x[0] / eq.radius, x[1] / eq.radius, x[2] / eq.radius};
    const Vec3 swing = cross(step.rotation, eq.centroid);
    step.translation = {x[3] - swing[0], x[4] - swing[1], x[5] - swing[2]};
    return step;
}

// The transform followed by the step: p -> exp(w) (R p + t) + dt.
frame::RigidTransform applyStep(const frame::RigidTransform& t, const Step& step) {
    const frame::RigidTransform update{exponential(step.rotation), step.translation};
    frame::RigidTransform out = frame::compose(update, t);
    out.rotation = orthonormalised(out.rotation);
    return out;
}

bool usableSeed(const frame::RigidTransform& seed) {
    return frame::rotationError(seed.rotation) < kMaxSeedRotationError &&
           std::all_of(seed.translationMeters.begin(), seed.translationMeters.end(),
                       [](double v) { return std::isfinite(v); });
}

} // namespace

bool DepthCloud::usable() const {
    if (depth == nullptr || !intrinsics.valid())
        return false;
    const frame::Plane<float>& d = depth->depthMeters;
    return !d.empty() && d.width == intrinsics.width && d.height == intrinsics.height &&
           d.pixels.size() == static_cast<std::size_t>(d.width) * d.height;
}

OverlapFigure overlapConsistency(const DepthCloud& a, const DepthCloud& b, const frame::RigidTransform& aToB,
                                 const OverlapParams& params) {
    if (!a.usable() || !b.usable())
        return {};
    const std::vector<Vec3> points = samplePoints(a, params.association.stride);
    Surface surface(b, params.association);
    return figureOf(associate(points, aToB, surface, params.maxDistanceMeters), points.size());
}

const char* toString(IcpStatus status) {
    switch (status) {
    case IcpStatus::Ok:
        return "refined";
    case IcpStatus::Degenerate:
        return "degenerate: the overlap leaves some motion free";
    case IcpStatus::TooFewPoints:
        return "too little overlap";
    case IcpStatus::InvalidInput:
        return "invalid input";
    }
    return "?";
}

namespace {

// The iterations proper: re-associate under a shrinking gate, weigh, step. Stops with TooFewPoints as soon as
// too few pairs or inliers remain (the caller then restores the seed).
void iterate(const std::vector<Vec3>& points, Surface& surface, const IcpParams& params, IcpResult& result) {
    double gate = params.firstMaxDistanceMeters;
    for (int iteration = 1; iteration <= params.maxIterations; ++iteration) {
        const std::vector<Pair> pairs = associate(points, result.aToB, surface, gate);
        const std::vector<double> weights = tukeyWeights(pairs);
        const auto inliers = static_cast<std::size_t>(
            std::count_if(weights.begin(), weights.end(), [](double w) { return w > 0.0; }));
        if (pairs.size() < params.minPoints || inliers < params.minPoints) {
            result.status = IcpStatus::TooFewPoints;
            return;
        }
        const Step step = solve(pairs, weights, params.minConditionRatio);
        result.aToB = applyStep(result.aToB, step);
        result.iterations = iteration;
        result.inliers = inliers;
        result.conditionRatio = step.conditionRatio;
        result.constrainedDirections = step.constrainedDirections;
        const bool small = norm(step.rotation) * kRadToDeg < params.stopRotationDegrees &&
                           norm(step.translation) < params.stopTranslationMeters;
        if (small && gate <= params.lastMaxDistanceMeters) {
            result.converged = true;
            break;
        }
        gate = std::max(params.lastMaxDistanceMeters, gate * params.distanceShrink);
    }
    result.status =
        result.iterations > 0 && result.constrainedDirections < 6 ? IcpStatus::Degenerate : IcpStatus::Ok;
}

} // namespace

IcpResult refineAlignment(const DepthCloud& a, const DepthCloud& b, const frame::RigidTransform& seed,
                          const IcpParams& params) {
    IcpResult result;
    result.aToB = seed;
    if (!a.usable() || !b.usable() || !usableSeed(seed))
        return result;
    result.aToB.rotation = orthonormalised(seed.rotation);
    const std::vector<Vec3> points = samplePoints(a, params.figure.association.stride);
    Surface surface(b, params.figure.association);
    const auto figure = [&](const frame::RigidTransform& t) {
        return figureOf(associate(points, t, surface, params.figure.maxDistanceMeters), points.size());
    };
    result.before = figure(result.aToB);
    iterate(points, surface, params, result);
    if (result.status == IcpStatus::TooFewPoints)
        result.aToB = seed;
    result.after = figure(result.aToB);
    result.correction = frame::compose(result.aToB, frame::inverse(seed));
    result.correctionDegrees = rotationDegrees(result.correction);
    result.correctionMm = norm(result.correction.translationMeters) * kMetersToMm;
    return result;
}

double rotationDegrees(const frame::RigidTransform& t) {
    // From both the sine (the skew part) and the cosine (the trace): acos alone loses half the digits of a
    // small angle.
    const auto& r = t.rotation;
    const Vec3 skew{r[7] - r[5], r[2] - r[6], r[3] - r[1]};
    return std::atan2(0.5 * norm(skew), 0.5 * (r[0] + r[4] + r[8] - 1.0)) * kRadToDeg;
}

frame::RigidTransform relativeTransform(const frame::Pose& a, const frame::Pose& b) {
    return frame::compose(frame::inverse(frame::rigidFromPose(b)), frame::rigidFromPose(a));
}

} // namespace dc::processing
