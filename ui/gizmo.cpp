#include "ui/gizmo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace dc::ui {

namespace {

constexpr int kArrowSamples = 8; // enough to break an arrow cleanly where it passes behind the eye
constexpr int kRingSamples = 64;
// Nearer the eye than this (clip w), a point has no place on the panel.
constexpr double kMinClipW = 1e-6;
// A handle whose axis projects shorter than this or a drag this near the origin says nothing reliable.
constexpr double kMinPixels = 1.0;

glm::dvec3 unitAxis(int axis) {
    glm::dvec3 e(0.0);
    e[axis] = 1.0;
    return e;
}

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

double distanceToSegment(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Each point of `world` on the panel, the polyline broken where a point is behind the eye.
std::vector<std::vector<glm::dvec2>> polylines(const GizmoView& view, const std::vector<glm::dvec3>& world) {
    std::vector<std::vector<glm::dvec2>> lines(1);
    for (const glm::dvec3& p : world) {
        if (const auto at = projectToPanel(view, p))
            lines.back().push_back(*at);
        else if (!lines.back().empty())
            lines.emplace_back();
    }
    std::erase_if(lines, [](const std::vector<glm::dvec2>& l) { return l.size() < 2; });
    return lines;
}

// Row-major rotation by `radians` about the unit `axis` (Rodrigues).
std::array<double, 9> rotationAbout(const glm::dvec3& axis, double radians) {
    const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
    const double x = axis.x, y = axis.y, z = axis.z;
    return {c + x * x * k,     x * y * k - z * s, x * z * k + y * s, y * x * k + z * s, c + y * y * k,
            y * z * k - x * s, z * x * k - y * s, z * y * k + x * s, c + z * z * k};
}

// The distance along the axis through `origin` whose projection is the point of the axis's line on the
// panel nearest `at`: the projection along a line is a ratio of linear functions, inverted exactly, so
// that the grabbed point follows the mouse under perspective too.
std::optional<double> alongAxis(const GizmoView& view, const glm::dvec3& origin, const glm::dvec3& axis,
                                const glm::dvec2& p0, const glm::dvec2& direction, const glm::dvec2& at) {
    const glm::dvec2 q = p0 + glm::dot(at - p0, direction) * direction;
    const glm::dvec4 c0 = view.worldToClip * glm::dvec4(origin, 1.0);
    const glm::dvec4 c1 = view.worldToClip * glm::dvec4(axis, 0.0);
    // Solved on the panel's coordinate the line changes most along.
    const bool useX = std::abs(direction.x) >= std::abs(direction.y);
    const double ndc =
        useX ? 2.0 * q.x / view.viewportPixels.x - 1.0 : 1.0 - 2.0 * q.y / view.viewportPixels.y;
    const double a0 = useX ? c0.x : c0.y, a1 = useX ? c1.x : c1.y;
    const double denominator = a1 - ndc * c1.w;
    if (std::abs(denominator) < std::numeric_limits<double>::epsilon())
        return std::nullopt;
    const double s = (ndc * c0.w - a0) / denominator;
    if (c0.w + s * c1.w <= kMinClipW)
        return std::nullopt;
    return s;
}

frame::RigidTransform moveStep(int axisIndex, const GizmoView& view, const glm::dvec3& origin,
                               const glm::dvec2& from, const glm::dvec2& to) {
    const glm::dvec3 axis = unitAxis(axisIndex);
    const auto p0 = projectToPanel(view, origin);
    const auto p1 = projectToPanel(view, origin + kGizmoArrowMeters * axis);
    if (!p0 || !p1 || glm::length(*p1 - *p0) < kMinPixels)
        return {};
    const glm::dvec2 direction = glm::normalize(*p1 - *p0);
    const auto s0 = alongAxis(view, origin, axis, *p0, direction, from);
    const auto s1 = alongAxis(view, origin, axis, *p0, direction, to);
    if (!s0 || !s1)
        return {};
    frame::RigidTransform step;
    const glm::dvec3 t = (*s1 - *s0) * axis;
    step.translationMeters = {t.x, t.y, t.z};
    return step;
}

frame::RigidTransform turnStep(int axisIndex, const GizmoView& view, const glm::dvec3& origin,
                               const glm::dvec2& from, const glm::dvec2& to) {
    const auto centre = projectToPanel(view, origin);
    if (!centre)
        return {};
    const glm::dvec2 u = from - *centre, v = to - *centre;
    if (glm::length(u) < kMinPixels || glm::length(v) < kMinPixels)
        return {};
    // Which way a positive turn goes round on the panel: the next axis towards the one after it (x to y
    // about z), seen a millimetre from the origin, where the ring faces the eye or away from it.
    const auto b = projectToPanel(view, origin + 1e-3 * unitAxis((axisIndex + 1) % 3));
    const auto c = projectToPanel(view, origin + 1e-3 * unitAxis((axisIndex + 2) % 3));
    if (!b || !c)
        return {};
    const double facing = cross2(*b - *centre, *c - *centre);
    if (facing == 0.0)
        return {};
    const double swept = std::atan2(cross2(u, v), glm::dot(u, v));
    const double radians = facing > 0.0 ? swept : -swept;
    frame::RigidTransform step;
    step.rotation = rotationAbout(unitAxis(axisIndex), radians);
    const std::array<double, 3> o{origin.x, origin.y, origin.z};
    const std::array<double, 3> turned = step.apply(o);
    step.translationMeters = {o[0] - turned[0], o[1] - turned[1], o[2] - turned[2]};
    return step;
}

} // namespace

std::optional<glm::dvec2> projectToPanel(const GizmoView& view, const glm::dvec3& world) {
    const glm::dvec4 clip = view.worldToClip * glm::dvec4(world, 1.0);
    if (clip.w <= kMinClipW)
        return std::nullopt;
    return glm::dvec2((clip.x / clip.w + 1.0) * 0.5 * view.viewportPixels.x,
                      (1.0 - clip.y / clip.w) * 0.5 * view.viewportPixels.y);
}

GizmoShape projectGizmo(const GizmoView& view, const glm::dvec3& originWorld) {
    GizmoShape shape;
    shape.origin = projectToPanel(view, originWorld);
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 e = unitAxis(axis);
        std::vector<glm::dvec3> arrow;
        for (int i = 0; i <= kArrowSamples; ++i)
            arrow.push_back(originWorld + kGizmoArrowMeters * (static_cast<double>(i) / kArrowSamples) * e);
        shape.lines[static_cast<std::size_t>(axis)] = polylines(view, arrow);
        const glm::dvec3 b = unitAxis((axis + 1) % 3), c = unitAxis((axis + 2) % 3);
        std::vector<glm::dvec3> ring;
        for (int i = 0; i <= kRingSamples; ++i) {
            const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / kRingSamples;
            ring.push_back(originWorld + kGizmoRingMeters * (std::cos(a) * b + std::sin(a) * c));
        }
        shape.lines[static_cast<std::size_t>(axis) + 3] = polylines(view, ring);
    }
    return shape;
}

std::optional<GizmoHandle> pickGizmo(const GizmoShape& shape, const glm::dvec2& at, double radiusPixels) {
    // A ring must be clearly nearer than an arrow to take the mouse from it.
    constexpr double kArrowPreferencePixels = 0.5;
    std::optional<GizmoHandle> best;
    double bestDistance = radiusPixels;
    for (std::size_t h = 0; h < kGizmoHandles; ++h) {
        double d = std::numeric_limits<double>::infinity();
        for (const std::vector<glm::dvec2>& line : shape.lines[h])
            for (std::size_t i = 0; i + 1 < line.size(); ++i)
                d = std::min(d, distanceToSegment(at, line[i], line[i + 1]));
        const bool ringOverArrow = h >= 3 && best && !turns(*best);
        if (d <= bestDistance && (!ringOverArrow || d < bestDistance - kArrowPreferencePixels)) {
            best = static_cast<GizmoHandle>(h);
            bestDistance = d;
        }
    }
    return best;
}

frame::RigidTransform gizmoStep(GizmoHandle handle, const GizmoView& view, const glm::dvec3& originWorld,
                                const glm::dvec2& from, const glm::dvec2& to) {
    if (view.viewportPixels.x <= 0.0 || view.viewportPixels.y <= 0.0)
        return {};
    return turns(handle) ? turnStep(axisOf(handle), view, originWorld, from, to)
                         : moveStep(axisOf(handle), view, originWorld, from, to);
}

} // namespace dc::ui
