#include "render/orbit_camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace dc::render {

namespace {
constexpr float kSwingAmplitudeRadians = 0.6f; // about 35 degrees each way, enough to show the shadows
constexpr float kBaseSwingRate = 0.5f;         // radians of phase per second
constexpr float kNearClipMeters = 0.01f;
constexpr float kFarClipMeters = 100.0f;
} // namespace

OrbitView autoOffset(const AutoMotion& motion, double timeSeconds) {
    if (!motion.enabled)
        return {0.0f, 0.0f, 1.0f, glm::vec2(0.0f)};
    const auto phase = static_cast<float>(std::fmod(timeSeconds * kBaseSwingRate * motion.speed, 2.0 * M_PI));
    const float s = std::sin(phase);
    OrbitView offset;
    offset.yawRadians = kSwingAmplitudeRadians * s;
    offset.pitchRadians = 0.25f * kSwingAmplitudeRadians * std::sin(2.0f * phase);
    offset.zoom = 1.0f / (1.0f - 0.25f * std::clamp(motion.scaleMovement, 0.0f, 2.0f) * 0.5f * s * s);
    return offset;
}

glm::mat4 cloudViewProjection(const OrbitView& view, float pivotDepthMeters, float fovYRadians,
                              float aspect) {
    // OpenCV camera axes to OpenGL eye axes (y up, looking down -z).
    const glm::mat4 flip = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, -1.0f));
    const float pivot = std::max(pivotDepthMeters, 0.05f);
    const float distance = pivot / std::max(view.zoom, 0.05f);
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(view.panMeters, -distance));
    m = glm::rotate(m, view.pitchRadians, glm::vec3(1.0f, 0.0f, 0.0f));
    m = glm::rotate(m, view.yawRadians, glm::vec3(0.0f, 1.0f, 0.0f));
    m = glm::translate(m, glm::vec3(0.0f, 0.0f, pivot));
    const glm::mat4 projection =
        glm::perspective(fovYRadians, std::max(aspect, 1e-3f), kNearClipMeters, kFarClipMeters);
    return projection * m * flip;
}

float verticalFovRadians(const frame::Intrinsics& k) {
    if (!k.valid())
        return glm::radians(60.0f);
    return static_cast<float>(2.0 * std::atan(0.5 * k.height / k.fy));
}

} // namespace dc::render
