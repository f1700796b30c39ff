#include "ui/anchors.h"

#include <cstdio>

namespace dc::ui {

glm::dmat4 toMatrix(const frame::Pose& pose) {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            m[c][r] = pose.cameraToWorld[static_cast<std::size_t>(c * 4 + r)];
    return m;
}

void Anchors::add(const glm::vec3& cameraPoint, const std::optional<frame::Pose>& pose) {
    if (world_.size() >= kMaxAnchors)
        return;
    const glm::dvec4 p =
        (pose ? toMatrix(*pose) : glm::dmat4(1.0)) * glm::dvec4(glm::dvec3(cameraPoint), 1.0);
    world_.emplace_back(glm::vec3(p));
}

void Anchors::undo() {
    if (!world_.empty())
        world_.pop_back();
}

std::vector<glm::vec3> Anchors::inCameraFrame(const std::optional<frame::Pose>& pose) const {
    const glm::dmat4 worldToCamera = pose ? glm::inverse(toMatrix(*pose)) : glm::dmat4(1.0);
    std::vector<glm::vec3> out;
    out.reserve(world_.size());
    for (const glm::vec3& w : world_)
        out.emplace_back(glm::vec3(worldToCamera * glm::dvec4(glm::dvec3(w), 1.0)));
    return out;
}

double Anchors::segmentMeters(std::size_t i) const {
    if (i + 1 >= world_.size())
        return 0.0;
    return glm::length(glm::dvec3(world_[i + 1]) - glm::dvec3(world_[i]));
}

double Anchors::closingMeters() const {
    if (world_.size() < 3)
        return 0.0;
    return glm::length(glm::dvec3(world_.front()) - glm::dvec3(world_.back()));
}

double Anchors::areaSquareMeters() const {
    if (world_.size() < 3)
        return 0.0;
    // Fan from the first anchor: the sum of the triangles' vector areas is the polygon's vector area.
    glm::dvec3 sum(0.0);
    const glm::dvec3 origin(world_[0]);
    for (std::size_t i = 1; i + 1 < world_.size(); ++i)
        sum += glm::cross(glm::dvec3(world_[i]) - origin, glm::dvec3(world_[i + 1]) - origin);
    return 0.5 * glm::length(sum);
}

std::string formatLength(double meters) {
    char text[32];
    if (meters < 1.0)
        std::snprintf(text, sizeof text, "%.1f mm", meters * 1000.0);
    else
        std::snprintf(text, sizeof text, "%.3f m", meters);
    return text;
}

std::string formatArea(double squareMeters) {
    char text[40];
    if (squareMeters < 0.01)
        std::snprintf(text, sizeof text, "%.1f cm^2", squareMeters * 1e4);
    else
        std::snprintf(text, sizeof text, "%.4f m^2", squareMeters);
    return text;
}

} // namespace dc::ui
