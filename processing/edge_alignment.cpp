#include "processing/edge_alignment.h"

#include "processing/registration.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace dc::processing {

namespace {

constexpr double kNoEdge = std::numeric_limits<double>::infinity();
// Colour and depth edges this close (pixels, along either axis) to an unseen pixel are dropped: a gray
// region's border is marked by Canny at most a pixel from it.
constexpr int kUnseenMarginPx = 2;
// The 3x3 Sobel's response to a sharp step of one level: its smoothing column 1 2 1 sums to 4.
constexpr double kSobelStepGain = 4.0;
// The window scanned per depth edge grows with the square of the search distance.
constexpr double kMaxSearchLimitPx = 100.0;
// A pinhole focal length under a pixel is a field of view of nearly 180 degrees on any image, no camera's;
// refusing it also keeps px x z / fx finite for every finite depth.
constexpr double kMinFocalPx = 1.0;

std::string sizeText(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

bool paramsUsable(const EdgeAlignmentParams& p) {
    const auto finiteAtLeast = [](double v, double low) { return std::isfinite(v) && v >= low; };
    return finiteAtLeast(p.minJumpMeters, 0.0) && finiteAtLeast(p.relativeJump, 0.0) &&
           finiteAtLeast(p.cannyLowStepLevels, 0.0) &&
           finiteAtLeast(p.cannyHighStepLevels, p.cannyLowStepLevels) && p.cannyHighStepLevels > 0.0 &&
           p.maxSearchPx > 0.0 && p.maxSearchPx <= kMaxSearchLimitPx;
}

// Why the inputs cannot be measured; empty when they can.
std::string inputProblem(const frame::Plane<float>& depth, const RgbImage& colour, const frame::Intrinsics& k,
                         const Roi& roi, const EdgeAlignmentParams& p) {
    const std::string depthSize = sizeText(depth.width, depth.height);
    if (depth.empty() || depth.width <= 0 || depth.height <= 0 ||
        depth.pixels.size() != static_cast<std::size_t>(depth.width) * static_cast<std::size_t>(depth.height))
        return "the depth map is empty or malformed";
    if (colour.width != depth.width || colour.height != depth.height ||
        colour.pixels.size() != depth.pixels.size() * 3)
        return "the colour image (" + sizeText(colour.width, colour.height) +
               ") is not the depth map's size (" + depthSize + ")";
    if (!k.valid() || !(k.fx >= kMinFocalPx) || k.width != depth.width || k.height != depth.height)
        return "the depth intrinsics are not valid for the " + depthSize + " depth map";
    if (!roiInside(roi, depth.width, depth.height))
        return "the ROI lies outside the " + depthSize + " depth map";
    if (!paramsUsable(p))
        return "edge alignment parameters out of range (finite, non-negative jumps, low <= high Canny step, "
               "search distance in (0, " +
               numberText(kMaxSearchLimitPx) + "] px)";
    return {};
}

// 255 within kUnseenMarginPx of a pixel that is exactly kUnseenGray in all three channels.
cv::Mat nearUnseen(const cv::Mat& rgb) {
    cv::Mat mask;
    cv::inRange(rgb, cv::Scalar::all(kUnseenGray), cv::Scalar::all(kUnseenGray), mask);
    const int side = 2 * kUnseenMarginPx + 1;
    cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, {side, side}));
    return mask;
}

// Where the parabola through (-1, before), (0, at), (1, after) peaks, within half a pixel; 0 where `at` is no
// peak along this axis (a diagonal edge's neighbours on it may be stronger). A sharp step between two pixels
// gives both the same gradient and Canny marks the first: the parabola puts it halfway, on the step.
float peakOffset(float before, float at, float after) {
    const float curvature = before - 2.0f * at + after;
    if (!(curvature < 0.0f))
        return 0.0f;
    return std::clamp(0.5f * (before - after) / curvature, -0.5f, 0.5f);
}

struct ColourEdges {
    cv::Mat positions;  // CV_32FC2: x, y of the edge Canny found at a pixel; NaN where none
    cv::Mat distancePx; // CV_32F: from each pixel's centre to the nearest edge pixel's centre
    bool any = false;
};

ColourEdges colourEdges(const cv::Mat& rgb, const cv::Mat& unseen, const EdgeAlignmentParams& p) {
    cv::Mat luma, edges, gx, gy, magnitude;
    cv::cvtColor(rgb, luma, cv::COLOR_RGB2GRAY);
    // The colour was sampled down to the depth map's size, which already smooths a camera's noise: no blur.
    cv::Canny(luma, edges, p.cannyLowStepLevels * kSobelStepGain, p.cannyHighStepLevels * kSobelStepGain, 3,
              true);
    edges.setTo(0, unseen);
    cv::Sobel(luma, gx, CV_32F, 1, 0, 3);
    cv::Sobel(luma, gy, CV_32F, 0, 1, 3);
    cv::magnitude(gx, gy, magnitude);
    ColourEdges out;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    out.positions = cv::Mat(rgb.size(), CV_32FC2, cv::Scalar::all(nan));
    for (int y = 0; y < rgb.rows; ++y) {
        for (int x = 0; x < rgb.cols; ++x) {
            if (!edges.at<std::uint8_t>(y, x))
                continue;
            out.any = true;
            const auto m = [&](int u, int v) { return magnitude.at<float>(v, u); };
            cv::Vec2f at(static_cast<float>(x), static_cast<float>(y));
            if (std::abs(gx.at<float>(y, x)) >= std::abs(gy.at<float>(y, x))) {
                if (x > 0 && x + 1 < rgb.cols)
                    at[0] += peakOffset(m(x - 1, y), m(x, y), m(x + 1, y));
            } else if (y > 0 && y + 1 < rgb.rows) {
                at[1] += peakOffset(m(x, y - 1), m(x, y), m(x, y + 1));
            }
            out.positions.at<cv::Vec2f>(y, x) = at;
        }
    }
    if (out.any)
        cv::distanceTransform(edges == 0, out.distancePx, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    return out;
}

// The distance from (bx, by), a depth edge beside pixel (px, py), to the nearest colour edge; kNoEdge beyond
// maxSearchPx. The distance transform bounds the search: the nearest edge pixel's centre is d0 from the
// pixel, the depth edge lies half a pixel from it and an edge within half a pixel of its own pixel, so the
// nearest edge is within d0 + 1 and no edge is nearer than d0 - 1; pixels farther than d0 + 2 cannot hold it.
double nearestColourEdge(const ColourEdges& edges, int px, int py, float bx, float by, double maxSearchPx) {
    if (!edges.any)
        return kNoEdge;
    const double d0 = edges.distancePx.at<float>(py, px);
    if (d0 - 1.0 > maxSearchPx)
        return kNoEdge;
    const int reach = static_cast<int>(std::ceil(d0 + 2.0));
    double best = kNoEdge;
    for (int y = std::max(0, py - reach); y <= std::min(edges.positions.rows - 1, py + reach); ++y) {
        for (int x = std::max(0, px - reach); x <= std::min(edges.positions.cols - 1, px + reach); ++x) {
            const cv::Vec2f e = edges.positions.at<cv::Vec2f>(y, x);
            if (!std::isnan(e[0]))
                best = std::min(best,
                                std::hypot(static_cast<double>(e[0] - bx), static_cast<double>(e[1] - by)));
        }
    }
    return best <= maxSearchPx ? best : kNoEdge;
}

// Whether `farther` lies behind `nearer` by more than a depth edge's jump; never when either is unmeasured.
bool jumpsBehind(float nearer, float farther, const EdgeAlignmentParams& p) {
    return frame::isMeasured(nearer) && frame::isMeasured(farther) &&
           farther - nearer > std::max(p.minJumpMeters, p.relativeJump * nearer);
}

struct Scores {
    std::vector<double> px, mm;
    std::size_t depthEdges = 0;
};

// Each depth-edge pixel of the ROI away from unseen colour, and the distances of those that matched.
Scores scoreDepthEdges(const frame::Plane<float>& depth, const ColourEdges& edges, const cv::Mat& unseen,
                       const cv::Point& origin, const frame::Intrinsics& k, const Roi& roi,
                       const Polygon& polygon, const EdgeAlignmentParams& p) {
    static constexpr int kSteps[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    const std::vector<char> inRegion = polygonMask(polygon, roi);
    Scores s;
    const char* region = inRegion.data();
    for (int y = roi.y; y < roi.y + roi.height; ++y) {
        for (int x = roi.x; x < roi.x + roi.width; ++x) {
            const float z = depth.at(x, y);
            // The colour's edges and unseen mask cover only the search window at `origin`.
            const int wx = x - origin.x, wy = y - origin.y;
            if (!*region++ || !frame::isMeasured(z) || unseen.at<std::uint8_t>(wy, wx))
                continue;
            bool edge = false;
            double best = kNoEdge;
            for (const auto& [dx, dy] : kSteps) {
                const int qx = x + dx, qy = y + dy;
                if (qx < 0 || qy < 0 || qx >= depth.width || qy >= depth.height ||
                    !jumpsBehind(z, depth.at(qx, qy), p))
                    continue;
                edge = true;
                const float bx = static_cast<float>(wx) + 0.5f * static_cast<float>(dx);
                const float by = static_cast<float>(wy) + 0.5f * static_cast<float>(dy);
                best = std::min(best, nearestColourEdge(edges, wx, wy, bx, by, p.maxSearchPx));
            }
            if (!edge)
                continue;
            ++s.depthEdges;
            if (best != kNoEdge) {
                s.px.push_back(best);
                s.mm.push_back(best * static_cast<double>(z) / k.fx * kMetersToMm);
            }
        }
    }
    return s;
}

// The part of the colour whose edges can matter: the ROI grown by the search distance, the depth edge's
// half pixel and the 3x3 support of Canny's and Sobel's gradients (kept whole, so an edge near the window's
// border is marked as in the whole image; only Canny's hysteresis cannot follow a weak edge out and back in).
cv::Rect searchWindow(const Roi& roi, double maxSearchPx, const cv::Size& image) {
    const int margin = static_cast<int>(std::ceil(maxSearchPx)) + 4;
    const cv::Rect grown(roi.x - margin, roi.y - margin, roi.width + 2 * margin, roi.height + 2 * margin);
    return grown & cv::Rect(0, 0, image.width, image.height);
}

} // namespace

Expected<EdgeAlignment> measureEdgeAlignment(const frame::Plane<float>& depthMeters,
                                             const RgbImage& colourOnDepth,
                                             const frame::Intrinsics& depthIntrinsics, const Roi& roi,
                                             const Polygon& polygon, const EdgeAlignmentParams& params) {
    if (std::string problem = inputProblem(depthMeters, colourOnDepth, depthIntrinsics, roi, params);
        !problem.empty())
        return Error{problem};
    // OpenCV only reads through this header.
    const cv::Mat rgb(colourOnDepth.height, colourOnDepth.width, CV_8UC3,
                      const_cast<std::uint8_t*>(colourOnDepth.pixels.data()));
    // Only the ROI's neighbourhood: a 40 % region is a sixth of the image, and the edges are most of the
    // cost.
    const cv::Rect window = searchWindow(roi, params.maxSearchPx, rgb.size());
    const cv::Mat part = rgb(window);
    const cv::Mat unseen = nearUnseen(part);
    const ColourEdges edges = colourEdges(part, unseen, params);
    Scores s =
        scoreDepthEdges(depthMeters, edges, unseen, window.tl(), depthIntrinsics, roi, polygon, params);
    if (s.depthEdges == 0)
        return notEnoughSamples(polygon.empty() ? "no depth edge in the ROI"
                                                : "no depth edge in the polygon");
    if (s.px.empty())
        return notEnoughSamples("no depth edge matched a colour edge within " +
                                numberText(params.maxSearchPx) + " px");
    EdgeAlignment a;
    a.depthEdgePixels = s.depthEdges;
    a.matched = s.px.size();
    double sum = 0.0;
    for (double d : s.px)
        sum += d;
    a.meanPx = sum / static_cast<double>(s.px.size());
    a.medianPx = medianOf(std::move(s.px));
    a.medianMm = medianOf(std::move(s.mm));
    return a;
}

} // namespace dc::processing
