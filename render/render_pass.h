#pragma once

#include "render/render_target.h"

#include <glm/glm.hpp>

namespace dc::render {

// One pass of drawing into a target, for its lifetime. Begun, it binds the target, puts the pipeline state
// our shaders assume into a known state (ImGui's backend enables blending and scissoring between our
// passes) and clears color, and depth when the pass depth-tests. Ended, it binds framebuffer 0 again so
// that whatever draws next (ImGui) draws into the window, and flushes, so that the GPU starts on the pass
// at once.
class RenderPass {
public:
    RenderPass(const RenderTarget& target, const glm::vec3& clearColor, bool depthTest);
    ~RenderPass();
    RenderPass(const RenderPass&) = delete;
    RenderPass& operator=(const RenderPass&) = delete;
};

} // namespace dc::render
