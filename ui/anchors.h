#pragma once

#include "frame/frame.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace dc::ui {

// Anchors the user dropped on the cloud (the seed's tap-to-place anchors), kept in world coordinates so
// they stay on the surface they were placed on while the view rotates and, with a posed source, while the
// camera moves. Without a pose the depth camera's frame is the world.
class Anchors {
public:
    static constexpr std::size_t kMaxAnchors = 32;

    // Adds a point given in the camera frame of `pose` (identity when the frame has none).
    void add(const glm::vec3& cameraPoint, const std::optional<frame::Pose>& pose);
    void undo();
    void clear() { world_.clear(); }

    std::size_t size() const { return world_.size(); }
    bool empty() const { return world_.empty(); }
    const std::vector<glm::vec3>& world() const { return world_; }
    // The anchors in the camera frame of `pose`, where the cloud is drawn.
    std::vector<glm::vec3> inCameraFrame(const std::optional<frame::Pose>& pose) const;

    // Straight-line distance from anchor i to anchor i + 1, meters.
    double segmentMeters(std::size_t i) const;
    // The edge from the last anchor back to the first, which closes the polygon; 0 with fewer than three.
    double closingMeters() const;
    // Area of the polygon through the anchors in order (its vector area, so a planar polygon gets its exact
    // area), square meters; 0 with fewer than three.
    double areaSquareMeters() const;

private:
    std::vector<glm::vec3> world_;
};

glm::dmat4 toMatrix(const frame::Pose& pose);

// "734 mm" / "1.234 m"; "0.12 m²" style for areas.
std::string formatLength(double meters);
std::string formatArea(double squareMeters);

} // namespace dc::ui
