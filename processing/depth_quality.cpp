#include "processing/depth_quality.h"

#include "processing/parallel.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <random>
#include <string>

namespace dc::processing {

namespace {

// Where each edge crossing the horizontal line at y crosses it, ascending. An edge crosses when one end is
// above y and the other at or below it (PNPOLY's test), so a vertex on the line is counted once or twice,
// never ambiguously, and a horizontal edge never.
std::vector<double> crossingsAt(const Polygon& polygon, double y) {
    std::vector<double> crossings;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const auto& [xi, yi] = polygon[i];
        const auto& [xj, yj] = polygon[j];
        if ((yi > y) != (yj > y))
            crossings.push_back((xj - xi) * (y - yi) / (yj - yi) + xi);
    }
    std::sort(crossings.begin(), crossings.end());
    return crossings;
}

// For the pixels x0 .. x0 + inside.size() - 1 of row y: whether each centre is inside `polygon`, decided as
// insidePolygon decides it (an odd count of crossings to its right) from one set of crossings per row.
void markInside(const Polygon& polygon, int y, int x0, std::vector<char>& inside) {
    const std::vector<double> crossings = crossingsAt(polygon, y + 0.5);
    std::size_t left = 0; // crossings at or left of the centre
    for (std::size_t i = 0; i < inside.size(); ++i) {
        const double centre = x0 + static_cast<double>(i) + 0.5;
        while (left < crossings.size() && crossings[left] <= centre)
            ++left;
        inside[i] = (crossings.size() - left) % 2 == 1;
    }
}

using Matrix3 = std::array<std::array<double, 3>, 3>;

// DQT trims this fraction of the residuals from each end before its plane-fit RMS.
constexpr double kDqtTrimFraction = 0.005;
// Random planes are scored on at most this many points: the median of 2,000 residuals picks the same
// winner as the median of a million at a fraction of the cost; the inliers are then chosen among all.
constexpr std::size_t kScoreSamples = 2000;
// 1.4826 x the median |residual| estimates sigma for Gaussian noise.
constexpr double kMadToSigma = 1.4826;
// The adaptive sampling's bounds: a chance of never drawing three inliers, and the fewest samples drawn.
constexpr double kMissProbability = 1e-9;
constexpr int kMinIterations = 20;
// Fewer rows than twice this are classified on one core.
constexpr int kClassifyRowsPerPiece = 16;

// Cyclic Jacobi rotations on a symmetric 3x3 matrix: the rotations converge quadratically and never produce
// a NaN for finite input (a vanishing off-diagonal element is skipped, a huge theta makes t = 0). Returns
// the eigenvalues; `vectors` holds the eigenvectors as columns.
std::array<double, 3> jacobiEigen(Matrix3 a, Matrix3& vectors) {
    vectors = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0.0)
            break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0)
                    continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t =
                    (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0);
                const double s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double kp = a[k][p], kq = a[k][q];
                    a[k][p] = c * kp - s * kq;
                    a[k][q] = s * kp + c * kq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double pk = a[p][k], qk = a[q][k];
                    a[p][k] = c * pk - s * qk;
                    a[q][k] = s * pk + c * qk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double kp = vectors[k][p], kq = vectors[k][q];
                    vectors[k][p] = c * kp - s * kq;
                    vectors[k][q] = s * kp + c * kq;
                }
            }
        }
    }
    return {a[0][0], a[1][1], a[2][2]};
}

// n pointing away from the camera, so the same surface always gives the same normal and offset.
PlaneModel orientedPlane(std::array<double, 3> n, const Point3d& through) {
    if (n[2] < 0.0)
        n = {-n[0], -n[1], -n[2]};
    return {n, n[0] * through.x + n[1] * through.y + n[2] * through.z};
}

std::vector<Point3d> inliersOf(std::span<const Point3d> points, const RobustPlaneFit& fit) {
    std::vector<Point3d> out;
    out.reserve(points.size());
    std::copy_if(points.begin(), points.end(), std::back_inserter(out),
                 [&](const Point3d& p) { return fit.isInlier(p); });
    return out;
}

// The plane through three points; none when they are (nearly) collinear.
std::optional<PlaneModel> planeThrough(const Point3d& a, const Point3d& b, const Point3d& c) {
    const std::array<double, 3> u{b.x - a.x, b.y - a.y, b.z - a.z};
    const std::array<double, 3> v{c.x - a.x, c.y - a.y, c.z - a.z};
    const std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                  u[0] * v[1] - u[1] * v[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double scale =
        std::sqrt((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    if (!(length > 1e-9 * scale) || !std::isfinite(length))
        return std::nullopt;
    return orientedPlane({n[0] / length, n[1] / length, n[2] / length}, a);
}

// How many minimal samples make missing an all-inlier one less likely than kMissProbability, given the
// fraction of scored points within 3 sigma of the best plane so far (the standard adaptive stopping rule:
// a flat target with few outliers needs a few dozen, not hundreds). Never fewer than kMinIterations.
int samplesNeeded(const std::vector<double>& residuals, double medianResidual) {
    const double threshold = 3.0 * kMadToSigma * medianResidual;
    const auto within =
        std::count_if(residuals.begin(), residuals.end(), [&](double r) { return r <= threshold; });
    const double w = static_cast<double>(within) / static_cast<double>(residuals.size());
    const double allInliers = w * w * w;
    if (allInliers >= 1.0)
        return kMinIterations;
    if (allInliers <= 0.0)
        return std::numeric_limits<int>::max();
    const double n = std::ceil(std::log(kMissProbability) / std::log1p(-allInliers));
    return n >= static_cast<double>(std::numeric_limits<int>::max())
               ? std::numeric_limits<int>::max()
               : std::max(kMinIterations, static_cast<int>(n));
}

struct RandomPlane {
    PlaneModel plane;
    double medianResidual = 0.0;
    std::vector<Point3d> scored; // the subset it was scored on
};

// The minimal-sample plane with the smallest median |residual| over a random subset of the points (random,
// not a stride: a stride can alias with a pattern in the data, such as every fifth row being an edge).
std::optional<RandomPlane> bestRandomPlane(std::span<const Point3d> points, const RobustFitParams& params) {
    std::mt19937_64 random(params.seed);
    std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
    std::vector<Point3d> scored(std::min(points.size(), kScoreSamples));
    for (std::size_t k = 0; k < scored.size(); ++k)
        scored[k] = points[points.size() <= kScoreSamples ? k : pick(random)];
    std::vector<double> residuals(scored.size());
    std::optional<RandomPlane> best;
    int needed = params.iterations;
    for (int i = 0; i < std::min(needed, params.iterations); ++i) {
        const std::size_t a = pick(random), b = pick(random), c = pick(random);
        if (a == b || b == c || a == c)
            continue;
        const auto plane = planeThrough(points[a], points[b], points[c]);
        if (!plane)
            continue;
        for (std::size_t k = 0; k < scored.size(); ++k)
            residuals[k] = std::abs(plane->signedDistance(scored[k]));
        // Fewer than half the residuals below the best median puts this plane's median at or above it:
        // a count rejects most planes without ordering their residuals.
        if (best && static_cast<std::size_t>(std::count_if(residuals.begin(), residuals.end(), [&](double r) {
                        return r < best->medianResidual;
                    })) < residuals.size() / 2)
            continue;
        const double m = medianOf(residuals);
        if (best && m >= best->medianResidual)
            continue;
        best = RandomPlane{*plane, m, {}};
        needed = samplesNeeded(residuals, m);
    }
    if (best)
        best->scored = std::move(scored);
    return best;
}

// A total least-squares plane and what it leaves: the sum of the points' squared perpendicular distances to
// it is the scatter matrix's smallest eigenvalue, so the fit's RMS costs no second pass over the points.
struct LeastSquaresFit {
    PlaneModel plane;
    double sumOfSquaredResiduals = 0.0;
    std::size_t count = 0;
};

// The least-squares plane of n points whose sums about `o` are s1 (x y z) and s2 (xx xy xz yy yz zz).
Expected<LeastSquaresFit> planeOfSums(const Point3d& o, const std::array<double, 3>& s1,
                                      const std::array<double, 6>& s2, double n) {
    const Point3d c{o.x + s1[0] / n, o.y + s1[1] / n, o.z + s1[2] / n};
    const auto covariance = [&](int i, int j, int k) {
        return s2[static_cast<std::size_t>(k)] - s1[i] * s1[j] / n;
    };
    const Matrix3 cov{{{covariance(0, 0, 0), covariance(0, 1, 1), covariance(0, 2, 2)},
                       {covariance(0, 1, 1), covariance(1, 1, 3), covariance(1, 2, 4)},
                       {covariance(0, 2, 2), covariance(1, 2, 4), covariance(2, 2, 5)}}};
    Matrix3 vectors;
    const std::array<double, 3> values = jacobiEigen(cov, vectors);
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
    // Collinear or coincident points leave two eigenvalues at zero: any plane through the line fits.
    if (!(values[order[1]] > 1e-12 * values[order[2]]))
        return notEnoughSamples("the points are collinear or coincident");
    const int k = order[0];
    return LeastSquaresFit{orientedPlane({vectors[0][k], vectors[1][k], vectors[2][k]}, c),
                           std::max(values[k], 0.0), static_cast<std::size_t>(n)};
}

// Where a rank falls among many values without sorting them: the values counted into equal bins between
// their lowest and highest. Only the values of the bins that hold the ranks asked for are then put in
// order (a full selection over every residual or pixel was most of the quality figures' cost).
class RankBins {
public:
    explicit RankBins(std::span<const double> values) : counts_(kBins, 0) {
        const auto [lowest, highest] = std::minmax_element(values.begin(), values.end());
        low_ = *lowest;
        const double span = *highest - low_;
        scale_ = span > 0.0 ? static_cast<double>(kBins) / span : 0.0;
        for (double v : values)
            ++counts_[binOf(v)];
    }
    std::size_t binOf(double v) const {
        return std::min(static_cast<std::size_t>((v - low_) * scale_), kBins - 1);
    }
    // The bin holding the value of 0-based `rank` in ascending order, and how many values lie below it.
    std::pair<std::size_t, std::size_t> binOfRank(std::size_t rank) const {
        std::size_t bin = 0, below = 0;
        while (below + counts_[bin] <= rank)
            below += counts_[bin++];
        return {bin, below};
    }
    std::size_t count(std::size_t bin) const { return counts_[bin]; }

private:
    static constexpr std::size_t kBins = 4096;
    std::vector<std::size_t> counts_;
    double low_ = 0.0, scale_ = 0.0;
};

// The sum of the squares of `values` without the `trim` smallest and the `trim` largest, as sorting them and
// dropping both ends gives it, in linear time.
double sumOfSquaresTrimmed(std::span<const double> values, std::size_t trim) {
    const RankBins bins(values);
    // The bins of the first and the last value kept; every value below the first or above the last goes.
    const auto [lowBin, below] = bins.binOfRank(trim);
    const auto [highBin, belowHigh] = bins.binOfRank(values.size() - 1 - trim);
    const std::size_t above = values.size() - belowHigh - bins.count(highBin);
    double sum = 0.0;
    std::vector<double> edge;
    for (double v : values) {
        const std::size_t bin = bins.binOf(v);
        if (bin > lowBin && bin < highBin)
            sum += v * v;
        else if (bin == lowBin || bin == highBin)
            edge.push_back(v);
    }
    // The edge bins' values: what the trim leaves of each end goes, the middle stays.
    const auto first = edge.begin() + static_cast<std::ptrdiff_t>(trim - below);
    const auto last = edge.end() - static_cast<std::ptrdiff_t>(trim - above);
    std::nth_element(edge.begin(), first, edge.end());
    if (last != edge.end())
        std::nth_element(first, last, edge.end());
    for (auto it = first; it != last; ++it)
        sum += *it * *it;
    return sum;
}

// The two values in the middle of many values in ascending order (the same value twice for an odd count),
// through RankBins: only the middle bin is ordered.
std::pair<double, double> middleOfMany(std::span<const double> values) {
    const RankBins bins(values);
    const std::size_t mid = values.size() / 2;
    const auto [bin, below] = bins.binOfRank(mid);
    std::vector<double> middle;
    middle.reserve(bins.count(bin));
    for (double v : values)
        if (bins.binOf(v) == bin)
            middle.push_back(v);
    const auto at = middle.begin() + static_cast<std::ptrdiff_t>(mid - below);
    std::nth_element(middle.begin(), at, middle.end());
    if (values.size() % 2 == 1)
        return {*at, *at};
    // The value ranked just below the middle: the largest below it in this bin, or else the largest value
    // of the bins below.
    if (at != middle.begin())
        return {*std::max_element(middle.begin(), at), *at};
    double lower = -std::numeric_limits<double>::infinity();
    for (double v : values)
        if (bins.binOf(v) < bin)
            lower = std::max(lower, v);
    return {lower, *at};
}

// The least-squares sums of points about an origin among them: about the coordinates' origin, a plane a
// metre away would lose its millimetre thickness to the distance's square.
struct PlaneSums {
    Point3d origin;
    std::array<double, 3> s1{};
    std::array<double, 6> s2{}; // xx xy xz yy yz zz
    std::size_t count = 0;

    void add(const Point3d& p) {
        const double x = p.x - origin.x, y = p.y - origin.y, z = p.z - origin.z;
        s1[0] += x;
        s1[1] += y;
        s1[2] += z;
        s2[0] += x * x;
        s2[1] += x * y;
        s2[2] += x * z;
        s2[3] += y * y;
        s2[4] += y * z;
        s2[5] += z * z;
        ++count;
    }
    // Another's sums about the same origin.
    void merge(const PlaneSums& other) {
        for (std::size_t i = 0; i < s1.size(); ++i)
            s1[i] += other.s1[i];
        for (std::size_t i = 0; i < s2.size(); ++i)
            s2[i] += other.s2[i];
        count += other.count;
    }
    Expected<LeastSquaresFit> fit() const {
        if (count < 3)
            return notEnoughSamples(std::to_string(count) + " points, a plane needs 3");
        // A point that is not finite leaves a sum that is not (checked once here, not per point).
        const bool finiteSums = std::isfinite(s1[0] + s1[1] + s1[2]) &&
                                std::all_of(s2.begin(), s2.end(), [](double v) { return std::isfinite(v); });
        if (!finiteSums)
            return Error{"a point of the plane fit is not finite"};
        return planeOfSums(origin, s1, s2, static_cast<double>(count));
    }
};

template <class Keep>
Expected<LeastSquaresFit> leastSquaresWhere(std::span<const Point3d> points, Keep&& keep) {
    const auto first = std::find_if(points.begin(), points.end(), keep);
    if (first == points.end())
        return notEnoughSamples("0 points, a plane needs 3");
    PlaneSums sums{*first};
    for (auto it = first; it != points.end(); ++it)
        if (keep(*it))
            sums.add(*it);
    return sums.fit();
}

// DQT's trim removes a few hundredths of the residuals; where the points are many, their ends are found
// among candidates beyond bounds estimated on a random subset, in the same pass that sums the middle.
constexpr std::size_t kTailSamples = 4096;
constexpr std::size_t kTailSearchMinPoints = 20000;
constexpr std::uint64_t kTailSeed = 5;

struct TailBounds {
    double low = 0.0;
    double high = 0.0;
};

// The subset's residual quantiles at three times the trimmed fraction: each end's candidates are then about
// 1.5 % of the points, and fewer than the trim beyond a bound is a five-sigma event. None when the bounds do
// not separate (a noise-free plane).
std::optional<TailBounds> tailBounds(std::span<const Point3d> points, const PlaneModel& plane) {
    std::mt19937_64 random(kTailSeed);
    std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
    std::vector<double> sample(kTailSamples);
    for (double& r : sample)
        r = plane.signedDistance(points[pick(random)]);
    std::sort(sample.begin(), sample.end());
    const auto q = static_cast<std::size_t>(std::ceil(3.0 * kDqtTrimFraction * kTailSamples));
    const TailBounds bounds{sample[q], sample[kTailSamples - 1 - q]};
    if (!(bounds.low < bounds.high))
        return std::nullopt;
    return bounds;
}

// The sum of the squared residuals without the `trim` smallest and the `trim` largest, from one pass over
// the points; none when an end has fewer candidates than the trim (the exact selection then runs).
std::optional<double> trimmedSumByTails(std::span<const Point3d> points, const PlaneModel& plane,
                                        std::size_t trim) {
    const auto bounds = tailBounds(points, plane);
    if (!bounds)
        return std::nullopt;
    double sum = 0.0;
    std::vector<double> low, high;
    for (const Point3d& p : points) {
        const double r = plane.signedDistance(p);
        if (r <= bounds->low)
            low.push_back(r);
        else if (r >= bounds->high)
            high.push_back(r);
        else
            sum += r * r;
    }
    if (low.size() < trim || high.size() < trim)
        return std::nullopt;
    const auto lowKept = low.begin() + static_cast<std::ptrdiff_t>(trim);
    std::nth_element(low.begin(), lowKept, low.end());
    const auto highKept = high.end() - static_cast<std::ptrdiff_t>(trim);
    std::nth_element(high.begin(), highKept, high.end());
    for (auto it = lowKept; it != low.end(); ++it)
        sum += *it * *it;
    for (auto it = high.begin(); it != highKept; ++it)
        sum += *it * *it;
    return sum;
}

// DQT's plane-fit RMS of the points about their least-squares plane: the residuals without the 0.5 % at
// each end.
double dqtTrimmedRms(std::span<const Point3d> points, const PlaneModel& plane) {
    const auto trim =
        static_cast<std::size_t>(std::floor(kDqtTrimFraction * static_cast<double>(points.size())));
    const auto kept = static_cast<double>(points.size() - 2 * trim);
    if (points.size() >= kTailSearchMinPoints) {
        if (const auto sum = trimmedSumByTails(points, plane, trim))
            return std::sqrt(*sum / kept);
    }
    std::vector<double> residuals;
    residuals.reserve(points.size());
    for (const Point3d& p : points)
        residuals.push_back(plane.signedDistance(p));
    return std::sqrt(sumOfSquaresTrimmed(residuals, trim) / kept);
}

} // namespace

Error notEnoughSamples(const std::string& why) {
    return Error{std::string(kNotEnoughSamples) + ": " + why};
}

double medianOf(std::vector<double> values) {
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
    const double upper = values[mid];
    if (values.size() % 2 == 1)
        return upper;
    return 0.5 *
           (upper + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
}

Roi centredRoi(int imageWidth, int imageHeight, double percent) {
    const double f = std::clamp(percent, 0.0, 100.0) / 100.0;
    const int w = std::clamp(static_cast<int>(std::lround(imageWidth * f)), 1, std::max(1, imageWidth));
    const int h = std::clamp(static_cast<int>(std::lround(imageHeight * f)), 1, std::max(1, imageHeight));
    return {(imageWidth - w) / 2, (imageHeight - h) / 2, w, h};
}

bool roiInside(const Roi& roi, int imageWidth, int imageHeight) {
    return roi.width > 0 && roi.height > 0 && roi.x >= 0 && roi.y >= 0 && roi.x <= imageWidth - roi.width &&
           roi.y <= imageHeight - roi.height;
}

bool insidePolygon(const Polygon& polygon, double x, double y) {
    if (polygon.size() < 3)
        return false;
    const std::vector<double> crossings = crossingsAt(polygon, y);
    const auto right = std::count_if(crossings.begin(), crossings.end(), [x](double c) { return x < c; });
    return right % 2 == 1;
}

std::vector<char> polygonMask(const Polygon& polygon, const Roi& roi) {
    const std::size_t width = static_cast<std::size_t>(std::max(roi.width, 0));
    std::vector<char> mask(width * static_cast<std::size_t>(std::max(roi.height, 0)), 1);
    if (polygon.empty() || mask.empty())
        return mask;
    std::vector<char> inside(width);
    for (int y = 0; y < roi.height; ++y) {
        markInside(polygon, roi.y + y, roi.x, inside);
        std::copy(inside.begin(), inside.end(), mask.begin() + static_cast<std::ptrdiff_t>(y * width));
    }
    return mask;
}

Roi polygonBounds(const Polygon& polygon) {
    if (polygon.empty())
        return {};
    double minX = polygon[0][0], maxX = minX, minY = polygon[0][1], maxY = minY;
    for (const auto& [x, y] : polygon) {
        minX = std::min(minX, x);
        maxX = std::max(maxX, x);
        minY = std::min(minY, y);
        maxY = std::max(maxY, y);
    }
    const int x0 = static_cast<int>(std::floor(minX));
    const int y0 = static_cast<int>(std::floor(minY));
    return {x0, y0, static_cast<int>(std::ceil(maxX)) - x0, static_cast<int>(std::ceil(maxY)) - y0};
}

Expected<PlaneModel> fitPlaneLeastSquares(std::span<const Point3d> points) {
    const auto fit = leastSquaresWhere(points, [](const Point3d&) { return true; });
    if (!fit)
        return fit.error();
    return fit->plane;
}

Expected<RobustPlaneFit> fitPlaneRobust(std::span<const Point3d> points, const RobustFitParams& params) {
    if (points.size() < 3)
        return notEnoughSamples(std::to_string(points.size()) + " points, a plane needs 3");
    const auto best = bestRandomPlane(points, params);
    if (!best)
        return notEnoughSamples("no three points span a plane");
    const double threshold = params.inlierThresholdMeters.value_or(
        std::max(3.0 * kMadToSigma * best->medianResidual, kMinInlierThresholdMeters));
    const auto within = [&threshold](const PlaneModel& plane) {
        return
            [&threshold, plane](const Point3d& p) { return std::abs(plane.signedDistance(p)) <= threshold; };
    };
    // The random plane refined by least squares on its inliers among the scored subset (its offset then
    // moves by noise / sqrt(2000), far inside the threshold), then least squares over every point within
    // the threshold of that: one pass over the points, which are chosen as they are summed, never copied.
    // The RMS is over the points of the last fit, against the plane they gave.
    PlaneModel chooser = best->plane;
    if (const auto refined = leastSquaresWhere(std::span<const Point3d>(best->scored), within(chooser)))
        chooser = refined->plane;
    const auto fit = leastSquaresWhere(points, within(chooser));
    if (!fit)
        return fit.error();
    const LeastSquaresFit& last = *fit;
    RobustPlaneFit result;
    result.plane = last.plane;
    result.selectedBy = chooser;
    const double inliers = static_cast<double>(last.count);
    result.rmsMeters = std::sqrt(last.sumOfSquaredResiduals / inliers);
    result.inlierFraction = inliers / static_cast<double>(points.size());
    result.inlierThresholdMeters = threshold;
    return result;
}

Expected<double> dqtPlaneFitRms(std::span<const Point3d> points) {
    const auto plane = fitPlaneLeastSquares(points);
    if (!plane)
        return plane.error();
    return dqtTrimmedRms(points, *plane);
}

Expected<double> distanceAlongOpticalAxis(const PlaneModel& plane) {
    const double d = plane.offsetMeters / plane.normal[2];
    if (!(plane.normal[2] > 1e-9) || !std::isfinite(d))
        return Error{"the plane is parallel to the optical axis"};
    return d;
}

double angleToOpticalAxisDegrees(const PlaneModel& plane) {
    return std::acos(std::clamp(std::abs(plane.normal[2]), 0.0, 1.0)) * 180.0 / std::numbers::pi;
}

double zAccuracyPercent(double measuredMeters, double truthMeters) {
    return (measuredMeters - truthMeters) / truthMeters * 100.0;
}

Expected<double> subpixelRms(std::span<const Point3d> points, const PlaneModel& plane, double focalPixels,
                             double baselineMeters) {
    if (!(focalPixels > 0.0) || !(baselineMeters > 0.0))
        return Error{"subpixel RMS needs a positive focal length and baseline"};
    const double fb = focalPixels * baselineMeters;
    double sum = 0.0;
    std::size_t count = 0;
    for (const Point3d& p : points) {
        const double along = plane.normal[0] * p.x + plane.normal[1] * p.y + plane.normal[2] * p.z;
        const double zPlane = plane.offsetMeters * p.z / along;
        if (!(p.z > 0.0) || !(zPlane > 0.0) || !std::isfinite(zPlane))
            continue;
        const double error = fb / zPlane - fb / p.z;
        sum += error * error;
        ++count;
    }
    if (count == 0)
        return notEnoughSamples("no point's ray meets the plane in front of the camera");
    return std::sqrt(sum / static_cast<double>(count));
}

namespace {

bool differsSameSense(float d, float a, float b, float threshold) {
    return frame::isMeasured(a) && frame::isMeasured(b) &&
           ((a - d > threshold && b - d > threshold) || (d - a > threshold && d - b > threshold));
}

// One ROI row's neighbourhood in the depth map: the rows above and below (none at the image border) and
// the row's confidence (none when the map has no confidence of the depth's size).
struct RowView {
    const float* above;
    const float* row;
    const float* below;
    const std::uint8_t* confidence;
    int width;
};

// The thresholds copied into values of its own: the causes are written as bytes, which may alias anything,
// and a threshold read through the parameters would be loaded again for every sample.
struct Classifier {
    float nearMeters;
    float farMeters;
    float flyingThresholdMeters;
    std::uint8_t minConfidence;

    explicit Classifier(const QualityParams& p)
        : nearMeters(p.nearMeters), farMeters(p.farMeters), flyingThresholdMeters(p.flyingThresholdMeters),
          minConfidence(static_cast<std::uint8_t>(p.minConfidence)) {}

    SampleCause operator()(const RowView& v, int x) const {
        const float d = v.row[x];
        if (!frame::isMeasured(d))
            return SampleCause::NoMeasurement;
        if (d < nearMeters || d > farMeters)
            return SampleCause::OutOfRange;
        if (v.confidence && v.confidence[x] < minConfidence)
            return SampleCause::LowConfidence;
        const float t = flyingThresholdMeters;
        if ((x > 0 && x + 1 < v.width && differsSameSense(d, v.row[x - 1], v.row[x + 1], t)) ||
            (v.above && v.below && differsSameSense(d, v.above[x], v.below[x], t)))
            return SampleCause::FlyingPixel;
        return SampleCause::Valid;
    }
};

RowView rowView(const frame::DepthData& depth, int y) {
    const frame::Plane<float>& map = depth.depthMeters;
    const auto& confidence = depth.confidence;
    const bool withConfidence =
        !confidence.empty() && confidence.width == map.width && confidence.height == map.height;
    const auto rowOf = [&map](int r) { return &map.pixels[static_cast<std::size_t>(r) * map.width]; };
    return {y > 0 ? rowOf(y - 1) : nullptr, rowOf(y), y + 1 < map.height ? rowOf(y + 1) : nullptr,
            withConfidence ? &confidence.pixels[static_cast<std::size_t>(y) * confidence.width] : nullptr,
            map.width};
}

// The region's valid samples as points, in row order, and their least-squares sums (all that DQT's plain fit
// needs of them), built on both cores: each piece writes its rows where a count of the rows before it puts
// them and sums them about the first point; the pieces' sums are added in row order.
struct RegionPoints {
    std::vector<Point3d> points;
    PlaneSums sums;
};

RegionPoints regionPoints(const frame::DepthData& depth, const frame::Intrinsics& k, const Roi& r,
                          std::span<const SampleCause> causes, std::vector<Point3d> buffer) {
    std::vector<std::size_t> rowStart(static_cast<std::size_t>(r.height) + 1, 0);
    const auto width = static_cast<std::ptrdiff_t>(r.width);
    for (int y = 0; y < r.height; ++y) {
        const auto row = causes.begin() + y * width;
        rowStart[static_cast<std::size_t>(y) + 1] =
            rowStart[static_cast<std::size_t>(y)] +
            static_cast<std::size_t>(std::count(row, row + width, SampleCause::Valid));
    }
    // Each column's and row's ray slope once, not a division per sample.
    std::vector<double> slopeX(static_cast<std::size_t>(r.width)), slopeY(static_cast<std::size_t>(r.height));
    for (int x = 0; x < r.width; ++x)
        slopeX[static_cast<std::size_t>(x)] = (r.x + x - k.cx) / k.fx;
    for (int y = 0; y < r.height; ++y)
        slopeY[static_cast<std::size_t>(y)] = (r.y + y - k.cy) / k.fy;
    const auto pointAt = [&](int x, int y) {
        const double z = depth.depthMeters.at(r.x + x, r.y + y);
        return Point3d{slopeX[static_cast<std::size_t>(x)] * z, slopeY[static_cast<std::size_t>(y)] * z, z};
    };
    RegionPoints out{std::move(buffer), {}};
    out.points.resize(rowStart.back());
    if (out.points.empty())
        return out;
    const auto first = static_cast<std::size_t>(std::find(causes.begin(), causes.end(), SampleCause::Valid) -
                                                causes.begin());
    out.sums.origin = pointAt(static_cast<int>(first % r.width), static_cast<int>(first / r.width));
    std::map<int, PlaneSums> pieces;
    std::mutex piecesMutex;
    parallelRanges(r.height, kClassifyRowsPerPiece, [&](int begin, int end) {
        PlaneSums sums{out.sums.origin};
        Point3d* next = out.points.data() + rowStart[static_cast<std::size_t>(begin)];
        for (int y = begin; y < end; ++y) {
            const SampleCause* row = causes.data() + y * width;
            for (int x = 0; x < r.width; ++x) {
                if (row[x] != SampleCause::Valid)
                    continue;
                *next = pointAt(x, y);
                sums.add(*next++);
            }
        }
        const std::lock_guard lock(piecesMutex);
        pieces.emplace(begin, sums);
    });
    for (const auto& [begin, sums] : pieces)
        out.sums.merge(sums);
    return out;
}

Expected<PlaneFigures> planeFigures(const RegionPoints& region, const frame::Intrinsics& k,
                                    const QualityParams& params) {
    const std::vector<Point3d>& points = region.points;
    // The two fits share nothing but the points: one core each.
    std::optional<Expected<RobustPlaneFit>> fit;
    std::optional<Expected<double>> dqt;
    parallelRanges(2, 1, [&](int begin, int end) {
        for (int job = begin; job < end; ++job) {
            if (job == 0) {
                fit = fitPlaneRobust(points, params.fit);
            } else {
                const auto plain = region.sums.fit();
                if (plain)
                    dqt = dqtTrimmedRms(points, plain->plane);
                else
                    dqt = plain.error();
            }
        }
    });
    if (!*fit)
        return fit->error();
    const auto distance = distanceAlongOpticalAxis((*fit)->plane);
    if (!distance)
        return distance.error();
    if (!*dqt)
        return dqt->error();
    const RobustPlaneFit& robust = **fit;
    PlaneFigures f;
    f.plane = robust.plane;
    f.distanceMm = *distance * kMetersToMm;
    f.angleDeg = angleToOpticalAxisDegrees(robust.plane);
    f.planeFitRmsMm = robust.rmsMeters * kMetersToMm;
    f.planeFitRmsPercent = robust.rmsMeters / *distance * 100.0;
    f.inlierFraction = robust.inlierFraction;
    f.dqtPlaneFitRmsMm = **dqt * kMetersToMm;
    if (params.groundTruthMeters)
        f.zAccuracyPercent = zAccuracyPercent(*distance, *params.groundTruthMeters);
    if (params.baselineMeters) {
        const auto subpixel =
            subpixelRms(inliersOf(points, robust), robust.plane, k.fx, *params.baselineMeters);
        if (subpixel)
            f.subpixelRms = *subpixel;
        f.expectedNoiseMm =
            expectedStereoNoiseMeters(*distance, k.fx, *params.baselineMeters, params.designSubpixelRms) *
            kMetersToMm;
    }
    return f;
}

} // namespace

double expectedStereoNoiseMeters(double zMeters, double focalPixels, double baselineMeters,
                                 double subpixelSigmaPixels) {
    return zMeters * zMeters * subpixelSigmaPixels / (focalPixels * baselineMeters);
}

std::array<std::uint8_t, 3> causeColour(SampleCause cause) {
    switch (cause) {
    case SampleCause::NoMeasurement:
        return {255, 0, 255};
    case SampleCause::OutOfRange:
        return {255, 140, 0};
    case SampleCause::LowConfidence:
        return {0, 200, 255};
    case SampleCause::FlyingPixel:
        return {255, 0, 0};
    case SampleCause::Valid:
    case SampleCause::OutsideRegion:
        break;
    }
    return {0, 0, 0};
}

RgbaImage causeOverlay(std::span<const SampleCause> causes, int width, int height) {
    RgbaImage image;
    if (width <= 0 || height <= 0 ||
        causes.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
        return image;
    image.width = width;
    image.height = height;
    image.pixels.assign(causes.size() * 4, 0);
    std::uint8_t* out = image.pixels.data();
    for (const SampleCause cause : causes) {
        if (cause != SampleCause::Valid && cause != SampleCause::OutsideRegion) {
            const auto rgb = causeColour(cause);
            out[0] = rgb[0];
            out[1] = rgb[1];
            out[2] = rgb[2];
            out[3] = 255;
        }
        out += 4;
    }
    return image;
}

std::vector<SampleCause> classifySamples(const frame::DepthData& depth, const QualityParams& params,
                                         FillBreakdown& counts) {
    const Roi& r = params.roi;
    std::vector<SampleCause> causes(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height));
    FillBreakdown total;
    std::size_t outsideTotal = 0;
    std::mutex countsMutex;
    const Classifier classify(params);
    // Rows on both cores: each piece counts its causes in locals (not an array indexed by the cause, whose
    // every increment would wait for the last) and adds them once.
    const bool withPolygon = !params.polygon.empty();
    parallelRanges(r.height, kClassifyRowsPerPiece, [&](int begin, int end) {
        std::size_t valid = 0, none = 0, range = 0, confidence = 0, flying = 0, outside = 0;
        SampleCause* out =
            causes.data() + static_cast<std::size_t>(begin) * static_cast<std::size_t>(r.width);
        std::vector<char> inside(static_cast<std::size_t>(r.width), 1);
        for (int y = r.y + begin; y < r.y + end; ++y) {
            const RowView view = rowView(depth, y);
            if (withPolygon)
                markInside(params.polygon, y, r.x, inside);
            for (int x = r.x; x < r.x + r.width; ++x, ++out) {
                const SampleCause c = inside[static_cast<std::size_t>(x - r.x)] ? classify(view, x)
                                                                                : SampleCause::OutsideRegion;
                *out = c;
                outside += c == SampleCause::OutsideRegion;
                valid += c == SampleCause::Valid;
                none += c == SampleCause::NoMeasurement;
                range += c == SampleCause::OutOfRange;
                confidence += c == SampleCause::LowConfidence;
                flying += c == SampleCause::FlyingPixel;
            }
        }
        const std::lock_guard lock(countsMutex);
        total.valid += valid;
        total.noMeasurement += none;
        total.outOfRange += range;
        total.lowConfidence += confidence;
        total.flyingPixel += flying;
        outsideTotal += outside;
    });
    total.roiSamples = causes.size() - outsideTotal; // a polygon's region is its box less what is outside
    counts = total;
    return causes;
}

Expected<FrameQuality> measureFrameQuality(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                           const QualityParams& params) {
    if (!intrinsics.valid())
        return Error{"the depth intrinsics cannot place points"};
    const Roi& r = params.roi;
    if (!roiInside(r, depth.depthMeters.width, depth.depthMeters.height))
        return Error{"the region of interest is outside the " + std::to_string(depth.depthMeters.width) +
                     "x" + std::to_string(depth.depthMeters.height) + " depth map"};
    FrameQuality q;
    q.causes = classifySamples(depth, params, q.fill);
    // The points' buffer is kept, one per thread: a new one (3.5 MB for a 40 % region of 1280x720) is
    // page-faulted in on every frame, a fifth of the figures' cost.
    static thread_local std::vector<Point3d> buffer;
    RegionPoints region = regionPoints(depth, intrinsics, r, q.causes, std::move(buffer));
    auto figures = planeFigures(region, intrinsics, params);
    buffer = std::move(region.points);
    if (figures)
        q.plane = std::move(*figures);
    else
        q.planeError = figures.error().message;
    return q;
}

NoiseWindow::NoiseWindow(const QualityParams& params, int windowFrames)
    : params_(params), windowFrames_(static_cast<std::size_t>(std::max(windowFrames, 1))),
      pixels_(static_cast<std::size_t>(std::max(params.roi.width, 0)) *
              static_cast<std::size_t>(std::max(params.roi.height, 0))),
      inverse_(windowFrames_ + 1) {
    for (std::size_t n = 1; n < inverse_.size(); ++n)
        inverse_[n] = 1.0 / static_cast<double>(n);
    inside_ = polygonMask(params.polygon, params.roi);
}

void NoiseWindow::add(const frame::DepthData& depth, std::optional<double> planeFitRmsMm) {
    if (!roiInside(params_.roi, depth.depthMeters.width, depth.depthMeters.height)) {
        add(depth, {}, planeFitRmsMm);
        return;
    }
    FillBreakdown counts;
    add(depth, classifySamples(depth, params_, counts), planeFitRmsMm);
}

void NoiseWindow::add(const frame::DepthData& depth, std::span<const SampleCause> causes,
                      std::optional<double> planeFitRmsMm) {
    // The frame leaving the window goes first, and its buffer takes the new frame: no allocation per frame.
    WindowFrame f;
    if (window_.size() >= windowFrames_) {
        leave(window_.front());
        f = std::move(window_.front());
        window_.pop_front();
    }
    f.depthMeters.assign(pixels_.size(), std::numeric_limits<float>::quiet_NaN());
    f.planeFitRmsMm = planeFitRmsMm;
    const Roi& r = params_.roi;
    if (causes.size() == pixels_.size() && roiInside(r, depth.depthMeters.width, depth.depthMeters.height)) {
        std::size_t i = 0;
        for (int y = r.y; y < r.y + r.height; ++y) {
            const float* row =
                &depth.depthMeters.pixels[static_cast<std::size_t>(y) * depth.depthMeters.width];
            for (int x = r.x; x < r.x + r.width; ++x, ++i)
                if (causes[i] == SampleCause::Valid)
                    f.depthMeters[i] = row[x];
        }
    }
    enter(f);
    window_.push_back(std::move(f));
}

// Welford's update: the mean and the sum of squared deviations without the cancellation of sum(x^2) - n m^2.
void NoiseWindow::enter(const WindowFrame& f) {
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
        const double x = f.depthMeters[i];
        if (std::isnan(x))
            continue;
        Running& p = pixels_[i];
        ++p.count;
        const double delta = x - p.mean;
        p.mean += delta * inverse_[p.count];
        p.m2 += delta * (x - p.mean);
    }
}

// Welford's update run backwards: the mean and m2 as they were before x entered.
void NoiseWindow::leave(const WindowFrame& f) {
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
        const double x = f.depthMeters[i];
        if (std::isnan(x))
            continue;
        Running& p = pixels_[i];
        if (p.count <= 1) {
            p = {};
            continue;
        }
        const double before = (p.count * p.mean - x) * inverse_[p.count - 1];
        p.m2 = std::max(0.0, p.m2 - (x - before) * (x - p.mean));
        p.mean = before;
        --p.count;
    }
}

Expected<double> NoiseWindow::temporalNoiseMm() const {
    if (window_.size() < 2)
        return notEnoughSamples("temporal noise needs at least 2 frames");
    // Every pixel counted has the same count (the window's length), so its deviation sqrt(m2 / (n - 1))
    // grows with m2: the middle pixels by m2, and only their square roots taken.
    const auto n = static_cast<std::uint32_t>(window_.size());
    std::vector<double> m2;
    m2.reserve(pixels_.size());
    for (const Running& p : pixels_) {
        if (p.count == n)
            m2.push_back(p.m2);
    }
    if (m2.empty())
        return notEnoughSamples("no pixel is valid in every frame of the window");
    const auto [lower, upper] = middleOfMany(m2);
    const auto deviationMm = [n](double v) { return std::sqrt(v / (n - 1)) * kMetersToMm; };
    return 0.5 * (deviationMm(lower) + deviationMm(upper));
}

frame::Plane<float> NoiseWindow::temporalStdMapMm() const {
    if (window_.empty())
        return {};
    frame::Plane<float> map(params_.roi.width, params_.roi.height, std::numeric_limits<float>::quiet_NaN());
    const auto n = static_cast<std::uint32_t>(window_.size());
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
        if (n >= 2 && pixels_[i].count == n)
            map.pixels[i] = static_cast<float>(std::sqrt(pixels_[i].m2 / (n - 1)) * kMetersToMm);
    }
    return map;
}

frame::Plane<float> NoiseWindow::fillMapPercent() const {
    if (window_.empty())
        return {};
    frame::Plane<float> map(params_.roi.width, params_.roi.height);
    const double scale = 100.0 / static_cast<double>(window_.size());
    for (std::size_t i = 0; i < pixels_.size(); ++i)
        map.pixels[i] = !inside_[i] ? std::numeric_limits<float>::quiet_NaN()
                                    : static_cast<float>(pixels_[i].count * scale);
    return map;
}

Expected<double> NoiseWindow::spatialNoiseMm() const {
    std::vector<double> rms;
    for (const WindowFrame& f : window_) {
        if (f.planeFitRmsMm)
            rms.push_back(*f.planeFitRmsMm);
    }
    if (rms.empty())
        return notEnoughSamples("no frame of the window had a plane fit");
    return medianOf(std::move(rms));
}

} // namespace dc::processing
