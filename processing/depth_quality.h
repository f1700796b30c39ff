#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/camera_image.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

// Depth quality figures of a flat target (issue 29), as Intel's Depth Quality Tool (DQT) reports them, plus a
// robust plane fit that a few stray samples cannot move. Pure CPU; doubles for every sum.
namespace dc::processing {

// A rectangle of depth pixels: columns x .. x + width - 1, rows y .. y + height - 1.
struct Roi {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    bool operator==(const Roi&) const = default;
};

// DQT's region of interest: centred, `percent` of the image's width and of its height (at least 1 pixel).
Roi centredRoi(int imageWidth, int imageHeight, double percent);
// Whether `roi` is non-empty and lies inside a width x height image.
bool roiInside(const Roi& roi, int imageWidth, int imageHeight);

// A polygon's vertices (x, y) in depth-map pixel coordinates: pixel (x, y) spans [x, x + 1) x [y, y + 1).
using Polygon = std::vector<std::array<double, 2>>;
// Whether (x, y) is inside `polygon` by the even-odd rule (a self-crossing lasso's overlaps are outside).
// A point exactly on an edge is inside when the polygon lies to its right or below it (larger x or y) and
// outside otherwise, as a rasterizer decides: two polygons sharing an edge never both hold a point on it.
// Fewer than 3 vertices hold nothing.
bool insidePolygon(const Polygon& polygon, double x, double y);
// The pixels that can hold a centre inside `polygon`: floor of its smallest x and y to the ceiling of its
// largest, unclamped; empty for no vertices.
Roi polygonBounds(const Polygon& polygon);
// Which samples of `roi` (row-major, roi.width x roi.height) have their centres inside `polygon`, decided
// as insidePolygon decides; every one for an empty polygon.
std::vector<char> polygonMask(const Polygon& polygon, const Roi& roi);

struct Point3d {
    double x = 0.0, y = 0.0, z = 0.0;
};

// The plane n . p = offsetMeters, |n| = 1, n pointing away from the camera (n.z >= 0).
struct PlaneModel {
    std::array<double, 3> normal{0.0, 0.0, 1.0};
    double offsetMeters = 0.0;
    double signedDistance(const Point3d& p) const {
        return normal[0] * p.x + normal[1] * p.y + normal[2] * p.z - offsetMeters;
    }
};

inline constexpr const char* kNotEnoughSamples = "not enough valid samples";
// kNotEnoughSamples with the reason, as one error line.
Error notEnoughSamples(const std::string& why);

inline constexpr double kMetersToMm = 1000.0;

// The median of `values`, the mean of the middle two for an even count; `values` must not be empty.
double medianOf(std::vector<double> values);

// Total least squares: the plane through the centroid whose normal is the covariance's smallest eigenvector
// (points are centred first, so a plane 20 m away loses no precision). An error with fewer than 3 points or
// when they are (nearly) collinear, coincident or not finite.
Expected<PlaneModel> fitPlaneLeastSquares(std::span<const Point3d> points);

struct RobustFitParams {
    // Perpendicular distance within which a point is an inlier. Unset: 3x the noise estimated from the
    // median residual of the best random plane (1.4826 x median |r| is sigma for Gaussian noise), at least
    // kMinInlierThresholdMeters so noise-free data keeps its points.
    std::optional<double> inlierThresholdMeters;
    int iterations = 200;
    std::uint64_t seed = 29;
};
inline constexpr double kMinInlierThresholdMeters = 0.0005;

struct RobustPlaneFit {
    PlaneModel plane;
    double rmsMeters = 0.0;      // perpendicular residuals of the inliers
    double inlierFraction = 0.0; // inliers / points
    double inlierThresholdMeters = 0.0;
    // The plane the inliers were chosen against (the fit before the last): a point is an inlier when
    // it lies within the threshold of it.
    PlaneModel selectedBy;
    bool isInlier(const Point3d& p) const {
        return std::abs(selectedBy.signedDistance(p)) <= inlierThresholdMeters;
    }
};

// RANSAC with least-median-of-squares scoring (LMedS): minimal 3-point samples drawn with a seeded generator,
// the one whose median |residual| is smallest wins (no threshold needed to choose it, and it tolerates up
// to half the points being outliers); then least squares on its inliers, the inliers chosen again against
// that plane and least squares once more.
Expected<RobustPlaneFit> fitPlaneRobust(std::span<const Point3d> points, const RobustFitParams& params = {});

// DQT's plane-fit RMS, as implemented here: a least-squares plane through ALL the points, their signed
// perpendicular residuals sorted, floor(0.5 % of the count) removed from each end (the most negative and
// the most positive ones), the RMS of the rest, in meters.
Expected<double> dqtPlaneFitRms(std::span<const Point3d> points);

// Where the plane crosses the principal ray (0, 0, z): offset / n.z, meters. An error for a plane parallel
// to the optical axis (it never crosses it).
Expected<double> distanceAlongOpticalAxis(const PlaneModel& plane);
// Angle between the plane's normal and the optical axis, degrees (0: the plane faces the camera).
double angleToOpticalAxisDegrees(const PlaneModel& plane);
// DQT's Z accuracy: (measured - truth) / truth, percent.
double zAccuracyPercent(double measuredMeters, double truthMeters);

// DQT's subpixel RMS, in pixels: a stereo camera measures disparity d = f B / z, so each point's error is
// expressed as disparity: f B / zPlane - f B / zMeasured, where zPlane is the depth at which the point's
// own pixel ray (p / p.z) meets the plane (offset p.z / (n . p)). RMS of that over `points`.
Expected<double> subpixelRms(std::span<const Point3d> points, const PlaneModel& plane, double focalPixels,
                             double baselineMeters);

// The stereo model's depth noise at distance z: disparity d = f B / z measured to sigmaD pixels gives
// sigmaZ = z^2 sigmaD / (f B), meters. Drawn against the measured plane-fit RMS it tells a camera at its
// design noise from one with a calibration fault (which is worse than the model at every distance).
double expectedStereoNoiseMeters(double zMeters, double focalPixels, double baselineMeters,
                                 double subpixelSigmaPixels);

// Why an ROI sample is not valid. Each sample has one cause, checked in this order.
// OutsideRegion: a sample of the polygon's bounding box whose centre is outside the polygon; it belongs to no
// count of the region (not even roiSamples) and is never valid.
enum class SampleCause : std::uint8_t {
    Valid,
    NoMeasurement,
    OutOfRange,
    LowConfidence,
    FlyingPixel,
    OutsideRegion
};

// Each cause's colour where the panels show why samples are missing: saturated hues that none of the
// depth colormaps' ends resemble (no measurement magenta, out of range orange, low confidence cyan, flying
// pixel red). A valid sample, or one outside the region, has none.
std::array<std::uint8_t, 3> causeColour(SampleCause cause);
// The region's samples as an overlay for the image panels: each missing sample in its cause's colour, opaque,
// every valid one and every one outside the region transparent. `causes` are roi.width x roi.height
// (classifySamples).
RgbaImage causeOverlay(std::span<const SampleCause> causes, int width, int height);

struct QualityParams {
    Roi roi;
    // Empty: the region is `roi`. Else the region is the samples whose pixel centres (x + 0.5, y + 0.5) are
    // inside this polygon (insidePolygon), and `roi` is the rectangle classified: the polygon's bounds
    // (polygonBounds) clamped to the map.
    Polygon polygon;
    float nearMeters = 0.0f;
    float farMeters = std::numeric_limits<float>::infinity();
    frame::Confidence minConfidence = frame::Confidence::Low;
    // A flying pixel is a sample at depth d whose two horizontal neighbours (left and right) are both
    // measured and both differ from d by more than this in the same sense (both nearer than d - t, or both
    // farther than d + t), or likewise its two vertical neighbours (above and below). A slanted surface
    // changes depth monotonically across a pixel, so it is never flagged; a lone sample left between a
    // foreground edge and the background, or a spike, is. Neighbours outside the ROI count; at the image
    // border that direction is not tested.
    float flyingThresholdMeters = 0.05f;
    RobustFitParams fit;
    std::optional<double> groundTruthMeters;
    std::optional<double> baselineMeters; // a stereo camera's; unset: no subpixel RMS, no expected noise
    // The camera's design subpixel accuracy (RMS, pixels) for the expected noise: 0.08 is what Intel
    // quotes for its D4xx cameras.
    double designSubpixelRms = 0.08;
};

struct FillBreakdown {
    std::size_t roiSamples = 0; // the region's samples: a polygon's bounding box counts only those inside
    std::size_t valid = 0;
    std::size_t noMeasurement = 0; // 0, NaN, inf or negative
    std::size_t outOfRange = 0;    // outside [nearMeters, farMeters]
    std::size_t lowConfidence = 0; // below minConfidence
    std::size_t flyingPixel = 0;
    double fraction(std::size_t count) const {
        return roiSamples ? static_cast<double>(count) / static_cast<double>(roiSamples) : 0.0;
    }
    double fillRate() const { return fraction(valid); }
};

// The cause of every ROI sample (roi.width x roi.height, row-major), counted into `counts`.
std::vector<SampleCause> classifySamples(const frame::DepthData& depth, const QualityParams& params,
                                         FillBreakdown& counts);

struct PlaneFigures {
    PlaneModel plane;
    double distanceMm = 0.0;
    double angleDeg = 0.0;
    double planeFitRmsMm = 0.0;
    double planeFitRmsPercent = 0.0; // of distanceMm
    double inlierFraction = 0.0;
    double dqtPlaneFitRmsMm = 0.0;
    std::optional<double> zAccuracyPercent;
    std::optional<double> subpixelRms;
    std::optional<double>
        expectedNoiseMm; // expectedStereoNoiseMeters at distanceMm, where a baseline is known
};

struct FrameQuality {
    FillBreakdown fill;
    std::vector<SampleCause> causes;   // every ROI sample's, as classifySamples gives them
    std::optional<PlaneFigures> plane; // unset: planeError says why
    std::string planeError;
};

// Every figure of one depth frame over params.roi (which must lie inside the depth map: an error if not, or
// if the intrinsics cannot place points).
Expected<FrameQuality> measureFrameQuality(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                           const QualityParams& params);

// Noise over the last `windowFrames` frames of a static scene. Temporal: each ROI pixel's standard
// deviation over the window (Welford's running mean and variance, updated as a frame enters and as it
// leaves the window), the median over the pixels valid in every frame of the window, mm. Spatial: the median
// over the window of each frame's plane-fit RMS, mm.
class NoiseWindow {
public:
    NoiseWindow(const QualityParams& params, int windowFrames);
    // One frame: its depth (classified as measureFrameQuality does) and its plane-fit RMS when it had one.
    void add(const frame::DepthData& depth, std::optional<double> planeFitRmsMm);
    // The same with the frame's causes already found (FrameQuality::causes), so they are not found twice.
    void add(const frame::DepthData& depth, std::span<const SampleCause> causes,
             std::optional<double> planeFitRmsMm);
    Expected<double> temporalNoiseMm() const;
    Expected<double> spatialNoiseMm() const;
    std::size_t frames() const { return window_.size(); }
    // Per pixel of the region (roi.width x roi.height): the temporal deviation, mm, where the pixel was valid
    // in every frame of the window (NaN elsewhere, as temporalNoiseMm counts them), and the percentage of the
    // window's frames in which it was valid (NaN outside a polygon). Empty before the first frame.
    frame::Plane<float> temporalStdMapMm() const;
    frame::Plane<float> fillMapPercent() const;

private:
    struct Running {
        std::uint32_t count = 0;
        double mean = 0.0;
        double m2 = 0.0;
    };
    struct WindowFrame {
        std::vector<float> depthMeters; // NaN where the sample is not valid
        std::optional<double> planeFitRmsMm;
    };
    void enter(const WindowFrame& f);
    void leave(const WindowFrame& f);

    QualityParams params_;
    std::size_t windowFrames_;
    std::deque<WindowFrame> window_;
    std::vector<Running> pixels_;
    std::vector<char> inside_;    // per pixel: inside the polygon (all without one)
    std::vector<double> inverse_; // 1 / n for every count a pixel can reach: multiplications, not divisions
};

} // namespace dc::processing
