#include "render/cloud_pick.h"

#include "processing/confidence_filter.h"
#include "processing/point_cloud.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace dc::render {

namespace {

struct Candidate {
    PickedSample sample;
    float viewDepth = 0.0f; // clip w: distance along the view direction
    float cursorDistanceSquared = 0.0f;
};

// Samples of the cloud drawn within the radius of the cursor.
std::vector<Candidate> candidatesNearCursor(const frame::DepthData& depth, const frame::Intrinsics& k,
                                            const PickQuery& query) {
    const frame::Plane<float>& d = depth.depthMeters;
    const bool hasConfidence = !depth.confidence.empty();
    const float radiusSquared = query.radiusPixels * query.radiusPixels;
    std::vector<Candidate> out;
    for (int v = 0; v < d.height; ++v) {
        for (int u = 0; u < d.width; ++u) {
            const float z = d.at(u, v);
            const std::uint8_t level = hasConfidence ? depth.confidence.at(u, v) : 2;
            if (!processing::keepSample(z, level, query.minConfidence, query.nearMeters))
                continue;
            const auto p = processing::unproject(u, v, z, k);
            const glm::vec4 clip = query.viewProjection * glm::vec4(p[0], p[1], p[2], 1.0f);
            if (clip.w <= 0.0f || clip.z < -clip.w || clip.z > clip.w)
                continue;
            // NDC y points up, image rows go down.
            const glm::vec2 pixel{(clip.x / clip.w + 1.0f) * 0.5f * query.imageSize.x,
                                  (1.0f - clip.y / clip.w) * 0.5f * query.imageSize.y};
            const glm::vec2 offset = pixel - query.cursorPixels;
            const float distanceSquared = glm::dot(offset, offset);
            if (distanceSquared <= radiusSquared)
                out.push_back({{u, v, {p[0], p[1], p[2]}}, clip.w, distanceSquared});
        }
    }
    return out;
}

} // namespace

std::optional<PickedSample> pickCloudSample(const frame::DepthData& depth,
                                            const frame::Intrinsics& depthIntrinsics,
                                            const PickQuery& query) {
    if (!depthIntrinsics.valid() || depth.depthMeters.empty() || query.imageSize.x <= 0.0f ||
        query.imageSize.y <= 0.0f)
        return std::nullopt;
    const std::vector<Candidate> candidates = candidatesNearCursor(depth, depthIntrinsics, query);
    if (candidates.empty())
        return std::nullopt;
    // Points behind the front surface are hidden, so only the front surface counts; on it, the sample
    // whose centre is nearest the cursor is the one under it.
    float front = std::numeric_limits<float>::infinity();
    for (const Candidate& c : candidates)
        front = std::min(front, c.viewDepth);
    const float surfaceDepth = front * 1.02f + 0.01f;
    const Candidate* best = nullptr;
    for (const Candidate& c : candidates)
        if (c.viewDepth <= surfaceDepth && (!best || c.cursorDistanceSquared < best->cursorDistanceSquared))
            best = &c;
    return best->sample;
}

} // namespace dc::render
