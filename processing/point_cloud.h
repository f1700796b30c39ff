#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/depth_quality.h"

#include <array>
#include <cstdint>
#include <vector>

namespace dc::processing {

// A point of the cloud in the depth camera's frame (OpenCV axes, meters) with its color and confidence.
struct CloudPoint {
    float x = 0, y = 0, z = 0;
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint8_t confidence = 0;
};

// Pixel (u, v) at depth z through intrinsics k, in float as the vertex shader computes it.
inline std::array<float, 3> unproject(int u, int v, float depthMeters, const frame::Intrinsics& k) {
    return {(static_cast<float>(u) - static_cast<float>(k.cx)) * depthMeters / static_cast<float>(k.fx),
            (static_cast<float>(v) - static_cast<float>(k.cy)) * depthMeters / static_cast<float>(k.fy),
            depthMeters};
}

// The camera-image pixel whose area matches depth pixel (u, v)'s centre, as the cloud's shader samples it:
// depth and image cover the same field of view at their own resolutions.
inline std::array<int, 2> cameraPixelOf(int u, int v, int depthWidth, int depthHeight,
                                        const frame::CapturedImage& image) {
    return {static_cast<int>((static_cast<float>(u) + 0.5f) * static_cast<float>(image.width) /
                             static_cast<float>(depthWidth)),
            static_cast<int>((static_cast<float>(v) + 0.5f) * static_cast<float>(image.height) /
                             static_cast<float>(depthHeight))};
}

// What a cloud is made of: one depth map (with its confidence), the intrinsics that place it, and the colour
// of each sample. Every reader of the shown cloud (the renderer, picking, accumulation, the snapshot PLY)
// takes the same samples, so they all see the same points.
struct CloudSamples {
    const frame::DepthData* depth = nullptr;
    frame::Intrinsics intrinsics;      // of depth's resolution
    const RgbImage* colours = nullptr; // depth's size; null: every point mid-gray
    bool usable() const;
};

// The CPU twin of the rendered cloud: one point per kept depth sample (processing::keepSample) with its
// colour. Empty when there is no depth or the intrinsics are invalid.
std::vector<CloudPoint> buildPointCloud(const CloudSamples& samples, frame::Confidence minLevel,
                                        float nearMeters);
// The raw frame's cloud: sceneDepth coloured by framePointColours() (registered for a two-sensor camera).
std::vector<CloudPoint> buildPointCloud(const frame::Frame& frame, frame::Confidence minLevel,
                                        float nearMeters);

// A polyline in the depth camera's frame (OpenCV axes, meters).
using Polyline3 = std::vector<std::array<float, 3>>;

// The outline of `roi` on the surface the cloud draws: its border pixels walked from the top-left corner
// along the top row, the right column, the bottom row and the left column, every one of them or, on a
// long border, evenly spaced ones (about `maxVertices` in all, the four corners always among them), each
// placed by unproject() as the cloud places it. A border sample the cloud does not draw (keepSample)
// breaks the outline rather than pulling it to the camera: the result is its unbroken runs of two
// vertices or more, and a single run, back to its first vertex, when nothing breaks it. Empty for a
// region not inside the map or invalid intrinsics.
std::vector<Polyline3> roiOutline(const frame::DepthData& depth, const frame::Intrinsics& k, const Roi& roi,
                                  frame::Confidence minLevel, float nearMeters, int maxVertices);
// The same along a polygon region's edges (the pixels they pass through, at most maxVertices of them).
// Empty for fewer than 3 vertices or invalid intrinsics.
std::vector<Polyline3> roiOutline(const frame::DepthData& depth, const frame::Intrinsics& k,
                                  const Polygon& polygon, frame::Confidence minLevel, float nearMeters,
                                  int maxVertices);

} // namespace dc::processing
