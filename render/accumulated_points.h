#pragma once

#include "base/expected.h"
#include "processing/point_accumulator.h"
#include "render/gl_objects.h"

#include <glm/glm.hpp>

#include <cstdint>

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

private:
    gl::Program program_;
    gl::VertexArray vertexArray_;
    gl::Buffer buffer_;
    GLint worldToClip_ = -1;
    GLint pointSize_ = -1;
    std::size_t capacity_ = 0;
    std::size_t count_ = 0;
    std::uint64_t generation_ = ~0ull;
};

} // namespace dc::render
