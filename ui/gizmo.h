#pragma once

#include "frame/camera_model.h"

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <vector>

namespace dc::ui {

// The in-cloud gizmo that moves and rotates a further source (as Foxglove's editable transforms): an
// arrow along each world axis from the source's camera origin, and a ring about each. Its geometry lives
// here, free of ImGui, so that it can be tested on its own; the Cloud panel only draws and drives it.

// Arrows move along world x, y, z; rings turn about them (the axis is the handle's index modulo 3).
enum class GizmoHandle { MoveX, MoveY, MoveZ, TurnX, TurnY, TurnZ };
inline constexpr std::size_t kGizmoHandles = 6;

inline constexpr double kGizmoArrowMeters = 0.15;
// Inside the arrows, so that a ring and an arrow cross away from the arrow's tip.
inline constexpr double kGizmoRingMeters = 0.12;
// A handle is picked when the mouse is this close to it.
inline constexpr float kGizmoPickPixels = 6.0f;

inline int axisOf(GizmoHandle handle) {
    return static_cast<int>(handle) % 3;
}
inline bool turns(GizmoHandle handle) {
    return static_cast<int>(handle) >= 3;
}

// How the world reaches the panel: the cloud's matrix from the world to clip space, and the panel's size
// in pixels (the cloud image fills it).
struct GizmoView {
    glm::dmat4 worldToClip{1.0};
    glm::dvec2 viewportPixels{0.0};
};

// A world point in panel pixels (from the panel's top-left corner, y down); none behind the eye.
std::optional<glm::dvec2> projectToPanel(const GizmoView& view, const glm::dvec3& world);

// The gizmo on the panel: its origin and each handle as polylines, broken where it passes behind the eye.
struct GizmoShape {
    std::optional<glm::dvec2> origin;
    std::array<std::vector<std::vector<glm::dvec2>>, kGizmoHandles> lines;
};
GizmoShape projectGizmo(const GizmoView& view, const glm::dvec3& originWorld);

// The handle nearest `at` (panel pixels) within `radiusPixels`; an arrow wins a tie with a ring (a ring
// seen edge-on lies along an arrow).
std::optional<GizmoHandle> pickGizmo(const GizmoShape& shape, const glm::dvec2& at,
                                     double radiusPixels = kGizmoPickPixels);

// What dragging `handle` from `from` to `to` (panel pixels) does to the source, as a world-frame
// transform to compose onto its correction. An arrow moves it along its axis so that the point under the
// mouse stays under it; a ring turns it about its axis through the source's origin by the angle the mouse
// swept around the origin's place on the panel: T(o) R T(-o).
frame::RigidTransform gizmoStep(GizmoHandle handle, const GizmoView& view, const glm::dvec3& originWorld,
                                const glm::dvec2& from, const glm::dvec2& to);

} // namespace dc::ui
