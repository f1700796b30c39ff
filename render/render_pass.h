#pragma once

#include "render/render_target.h"

#include <glm/glm.hpp>

namespace dc::render {

// Starts drawing into `target`: binds it, puts the pipeline state our shaders assume into a known state
// (ImGui's backend enables blending and scissoring between our passes) and clears color, and depth when
// the pass depth-tests.
void beginPass(const RenderTarget& target, const glm::vec3& clearColor, bool depthTest);
// Binds framebuffer 0 again so that whatever draws next (ImGui) draws into the window.
void endPass();

} // namespace dc::render
