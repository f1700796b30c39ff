#include "render/panel_renderer.h"

#include "render/colormap.h"
#include "render/render_pass.h"

#include <glm/glm.hpp>

#include <string>
#include <utility>
#include <vector>

namespace dc::render {

namespace {

// Maps the fragment to the image, top row first: GL's window origin is bottom-left, while row 0 of the
// data (and of RenderTarget::readRgba()) is the top of the image.
constexpr const char* kPanelCommon = R"glsl(
uniform vec2 viewportSize;
out vec4 fragColor;

vec2 imageCoord() {
    return vec2(gl_FragCoord.x, viewportSize.y - gl_FragCoord.y) / viewportSize;
}

ivec2 texelUnder(ivec2 size) {
    return clamp(ivec2(imageCoord() * vec2(size)), ivec2(0), size - 1);
}
)glsl";

constexpr const char* kDepthMain = R"glsl(
uniform float minMeters;
uniform float inverseRangeMeters;
uniform float holeAlpha;

void main() {
    float d = texelFetch(depthMap, texelUnder(textureSize(depthMap, 0)), 0).r;
    fragColor = validDepth(d) ? vec4(colormapColor((d - minMeters) * inverseRangeMeters), 1.0)
                              : vec4(0.0, 0.0, 0.0, holeAlpha);
}
)glsl";

constexpr const char* kConfidenceMain = R"glsl(
void main() {
    uint level = texelFetch(confidenceMap, texelUnder(textureSize(confidenceMap, 0)), 0).r;
    fragColor = vec4(confidenceColor(level), 1.0);
}
)glsl";

// Thinner than any depth range worth showing; keeps a collapsed range from dividing by zero.
constexpr float kMinRangeMeters = 1e-6f;

Expected<gl::Program> linkPanel(const char* name, const char* main, Colormap colormap = Colormap::Jet) {
    const std::string fragment = std::string("#version 330 core\n") + kFrameTexturesGlsl +
                                 colormapGlsl(colormap) + kPanelCommon + main;
    Expected<gl::Program> program = gl::Program::link(gl::kFullscreenVertexShader, fragment);
    if (!program)
        return Error{std::string(name) + " panel shaders: " + program.error().message};
    FrameTextures::connectSamplers(*program);
    return program;
}

} // namespace

Status PanelRenderer::init() {
    std::vector<std::pair<Panel*, Expected<gl::Program>>> panels;
    for (int c = 0; c < kColormapCount; ++c)
        panels.emplace_back(&depth_[static_cast<std::size_t>(c)],
                            linkPanel("depth", kDepthMain, static_cast<Colormap>(c)));
    panels.emplace_back(&confidence_, linkPanel("confidence", kConfidenceMain));
    for (auto& [panel, program] : panels) {
        if (!program)
            return program.error();
        panel->program = std::move(program).value();
        panel->viewportSize = panel->program.uniformLocation("viewportSize");
        panel->minMeters = panel->program.uniformLocation("minMeters");
        panel->inverseRangeMeters = panel->program.uniformLocation("inverseRangeMeters");
        panel->holeAlpha = panel->program.uniformLocation("holeAlpha");
    }
    emptyVertexArray_ = gl::VertexArray::create();
    glUseProgram(0);
    return Status::success();
}

void PanelRenderer::renderDepth(RenderTarget& target, const FrameTextures& textures, float minMeters,
                                float maxMeters, Colormap colormap, DepthHoles holes) {
    const Panel& panel = depth_[static_cast<std::size_t>(colormap)];
    draw(target, textures, panel, [&] {
        glUniform1f(panel.minMeters, minMeters);
        glUniform1f(panel.inverseRangeMeters, 1.0f / glm::max(maxMeters - minMeters, kMinRangeMeters));
        glUniform1f(panel.holeAlpha, holes == DepthHoles::Transparent ? 0.0f : 1.0f);
    });
}

void PanelRenderer::renderConfidence(RenderTarget& target, const FrameTextures& textures) {
    draw(target, textures, confidence_, [] {});
}

// Clears the target to black and, where there is data, draws `panel` over it with the uniforms `setUniforms`
// sets beside the viewport size.
void PanelRenderer::draw(RenderTarget& target, const FrameTextures& textures, const Panel& panel,
                         const std::function<void()>& setUniforms) const {
    if (target.empty())
        return;
    const RenderPass pass(target, glm::vec3(0.0f), false);
    if (!panel.program || !textures.hasDepth())
        return;
    glUseProgram(panel.program.id());
    glUniform2f(panel.viewportSize, static_cast<float>(target.width()), static_cast<float>(target.height()));
    setUniforms();
    textures.bind();
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

} // namespace dc::render
