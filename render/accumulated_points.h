#pragma once

#include "base/expected.h"
#include "processing/point_accumulator.h"
#include "render/gl_objects.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace dc::render {

// The GPU copy of a PointAccumulator: one vertex buffer as large as the budget, updated with only the
// slots written since the last sync, so a 1M-point budget costs an upload of one frame's new points.
class AccumulatedPoints {
public:
    // Compiles the shaders; needs a current context.
    Status init();
    // Uploads what changed in `accumulator` (all of it after a clear or a new budget).
    void sync(processing::PointAccumulator& accumulator);
    // Draws the points into the bound framebuffer; the caller has begun the pass.
    void draw(const glm::mat4& worldToClip, float pointSizePixels) const;
    std::size_t pointCount() const { return count_; }
    // Changes whenever sync() changed what is drawn.
    std::uint64_t version() const { return version_; }
    // Keeps a CPU copy of the points as well, for the CPU cloud path (CloudSplatter::splatWorld); turning
    // it on copies everything at the next sync.
    void setCpuCopy(bool keep);
    const std::vector<processing::WorldPoint>& cpuCopy() const { return cpu_; }

private:
    gl::Program program_;
    gl::VertexArray vertexArray_;
    gl::Buffer buffer_;
    GLint worldToClip_ = -1;
    GLint pointSize_ = -1;
    std::size_t capacity_ = 0;
    std::size_t count_ = 0;
    std::uint64_t generation_ = ~0ull;
    std::uint64_t version_ = 0;
    bool keepCpu_ = false;
    std::vector<processing::WorldPoint> cpu_;
};

} // namespace dc::render
