#pragma once

#include "frame/frame.h"

#include <glm/glm.hpp>

namespace dc::render {

// The manual part of the cloud's view, edited by dragging (orbit), the wheel (zoom) and right-drag (pan).
// Angles orbit the pivot: a point on the optical axis at the scene's typical depth.
struct OrbitView {
    float yawRadians = 0.0f;
    float pitchRadians = 0.0f;
    float zoom = 1.0f;         // > 1 moves the eye towards the pivot
    glm::vec2 panMeters{0.0f}; // shifts the scene parallel to the screen
};

// The sample's automatic movement: the view swings from side to side around the pivot so the cloud's 3D
// shape (and the empty "shadow" behind foreground objects) shows, while "scale movement" adds a dolly
// towards the scene in time with the swing.
struct AutoMotion {
    bool enabled = true;
    float speed = 1.0f;         // multiples of the base swing rate (one swing in ~12.6 s)
    float scaleMovement = 1.0f; // 0 = pure rotation; 1 = the dolly moves up to 25% of the pivot distance
};

// The automatic offsets at time t (seconds), added to the manual view.
OrbitView autoOffset(const AutoMotion& motion, double timeSeconds);

// Maps points of the depth camera's frame (OpenCV axes: x right, y down, z forward, meters) to clip space.
// With a neutral OrbitView and no motion the cloud is seen exactly from the depth camera, so it lines up
// with the camera image; fovY then should be the depth camera's vertical field of view.
glm::mat4 cloudViewProjection(const OrbitView& view, float pivotDepthMeters, float fovYRadians, float aspect);

// The depth camera's vertical field of view, or 60 degrees for invalid intrinsics.
float verticalFovRadians(const frame::Intrinsics& k);

} // namespace dc::render
