#pragma once

#include "frame/frame.h"

#include <glm/glm.hpp>

#include <optional>

namespace dc::render {

// A depth sample found under the cursor in the rendered cloud.
struct PickedSample {
    int u = 0; // depth-map pixel
    int v = 0;
    glm::vec3 point{0.0f}; // in the depth camera's frame (OpenCV axes, meters), as the shader places it
};

struct PickQuery {
    glm::mat4 viewProjection{1.0f}; // the matrix the cloud was drawn with
    glm::vec2 cursorPixels{0.0f};   // in the cloud image, (0, 0) at its top-left corner
    glm::vec2 imageSize{1.0f};      // the cloud image's size in pixels
    float radiusPixels = 4.0f;      // how far from the cursor a point's centre may be
    frame::Confidence minConfidence = frame::Confidence::Low;
    float nearMeters = 0.0f;
};

// The drawn sample under the cursor: of the samples whose projected centres lie within the radius, those
// on the front-most surface (within 2% + 1 cm of the nearest), and of these the one nearest the cursor.
// Applies the cloud's own culling (confidence, near limit, invalid depth), so a hidden point can never be
// picked. Nothing for invalid intrinsics or an empty neighbourhood.
std::optional<PickedSample> pickCloudSample(const frame::DepthData& depth,
                                            const frame::Intrinsics& depthIntrinsics, const PickQuery& query);

} // namespace dc::render
