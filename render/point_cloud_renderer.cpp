#include "render/point_cloud_renderer.h"

#include "render/colormap.h"
#include "render/point_shaders.h"

#include "render/render_pass.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <string>

namespace dc::render {

namespace {

constexpr const char* kVertexMain = R"glsl(
const float kMaxFillPixels = 32.0; // render::kMaxFillPixels
uniform mat4 viewProjection;
uniform vec4 depthIntrinsics; // fx, fy, cx, cy in depth-map pixels
uniform uint minConfidence;
uniform float nearMeters;
uniform float pointSizePixels;
uniform float footprintPixels; // render::footprintPixelsPerDepth
uniform int coloring; // render::PointColoring
uniform float minMeters;
uniform float inverseRangeMeters;
uniform bool shaderColours; // camera colours made here (CameraColours) rather than read from colorMap
uniform vec4 tint;          // a > 0: every point this colour (render::CloudLayer::tint)

out vec3 pointColor;

void main() {
    ivec2 size = textureSize(depthMap, 0);
    ivec2 pixel = ivec2(gl_VertexID % size.x, gl_VertexID / size.x);
    float z = texelFetch(depthMap, pixel, 0).r;
    uint confidence = texelFetch(confidenceMap, pixel, 0).r;
    pointColor = vec3(0.0);
    if (!validDepth(z) || z < nearMeters || confidence < minConfidence) {
        // Outside the clip volume, so the point is clipped before rasterisation.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        gl_PointSize = 1.0;
        return;
    }
    vec2 xy = (vec2(pixel) - depthIntrinsics.zw) * z / depthIntrinsics.xy;
    gl_Position = viewProjection * vec4(xy, z, 1.0);
    gl_PointSize = max(pointSizePixels, min(ceil(z * footprintPixels / gl_Position.w), kMaxFillPixels));
    pointColor = coloring == 0 ? (shaderColours ? cameraPointColor(pixel, size, vec3(xy, z))
                                                : texelFetch(colorMap, pixel, 0).rgb)
               : coloring == 1 ? colormapColor((z - minMeters) * inverseRangeMeters)
                               : confidenceColor(confidence);
    if (tint.a > 0.0)
        pointColor = tint.rgb;
}
)glsl";

// A cube per instance, built from gl_VertexID (6 faces x 2 triangles), flat-lit from above the camera so
// its faces read as a solid among the points, as the sample draws its anchors.
constexpr const char* kAnchorVertexShader = R"glsl(#version 330 core
uniform mat4 viewProjection;
uniform vec3 anchors[32];
uniform float halfSize;
out vec3 pointColor;

const vec3 kNormals[6] = vec3[](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1),
                                vec3(0, 0, -1));
const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    vec3 n = kNormals[gl_VertexID / 6];
    vec3 t = abs(n.x) > 0.5 ? vec3(0, 1, 0) : vec3(1, 0, 0);
    vec2 c = kCorners[gl_VertexID % 6];
    vec3 local = n + c.x * t + c.y * cross(n, t);
    gl_Position = viewProjection * vec4(anchors[gl_InstanceID] + halfSize * local, 1.0);
    // OpenCV camera axes: y points down, so "above" is -y; the light also comes from behind the viewer.
    float lambert = max(dot(n, normalize(vec3(0.3, -0.8, -0.5))), 0.0);
    pointColor = vec3(1.0, 0.84, 0.25) * (0.35 + 0.65 * lambert);
}
)glsl";

// Shows CloudSplatter's keys: the colour where a point landed, at the depth it landed at (so anchors are
// hidden behind nearer points as on the GL_POINTS path); nothing where none did.
constexpr const char* kSplatFragmentShader = R"glsl(#version 330 core
uniform usampler2D splatKeys;
out vec4 fragColor;

void main() {
    uvec2 key = texelFetch(splatKeys, ivec2(gl_FragCoord.xy), 0).rg;
    if (key.y == 0xffffffffu)
        discard;
    gl_FragDepth = uintBitsToFloat(key.y);
    fragColor = vec4(vec3(uvec3(key.x, key.x >> 8, key.x >> 16) & 255u) / 255.0, 1.0);
}
)glsl";

} // namespace

// A rigid view keeps lengths, so the projection's scale along each screen axis is the length of the
// combined matrix's row for it: a sample z / f meters wide at clip w covers that times z / (f w)
// half-screens.
float footprintPixelsPerDepth(const CloudParams& params, const frame::Intrinsics& k, int width, int height) {
    if (!params.fillGaps || !k.valid())
        return 0.0f;
    const glm::mat4& m = params.viewProjection;
    const float rowX = glm::length(glm::vec3(m[0][0], m[1][0], m[2][0]));
    const float rowY = glm::length(glm::vec3(m[0][1], m[1][1], m[2][1]));
    return std::max(rowX * 0.5f * static_cast<float>(width) / static_cast<float>(k.fx),
                    rowY * 0.5f * static_cast<float>(height) / static_cast<float>(k.fy));
}

const char* toString(PointColoring coloring) {
    switch (coloring) {
    case PointColoring::Camera:
        return "camera";
    case PointColoring::Depth:
        return "depth";
    case PointColoring::Confidence:
        return "confidence";
    }
    return "camera";
}

Status PointCloudRenderer::init() {
    for (int c = 0; c < kColormapCount; ++c) {
        const std::string vertexShader = std::string("#version 330 core\n") + kFrameTexturesGlsl +
                                         kCameraColoursGlsl + colormapGlsl(static_cast<Colormap>(c)) +
                                         kVertexMain;
        Expected<gl::Program> program = gl::Program::link(vertexShader, kPointColorFragmentShader);
        if (!program)
            return Error{"point cloud shaders: " + program.error().message};
        CloudProgram& cloud = programs_[static_cast<std::size_t>(c)];
        cloud.program = std::move(program).value();
        const gl::Program& p = cloud.program;
        FrameTextures::connectSamplers(p);
        CameraColours::connectSamplers(p);
        cloud.uniforms = {p.uniformLocation("viewProjection"),
                          p.uniformLocation("depthIntrinsics"),
                          p.uniformLocation("minConfidence"),
                          p.uniformLocation("nearMeters"),
                          p.uniformLocation("pointSizePixels"),
                          p.uniformLocation("footprintPixels"),
                          p.uniformLocation("coloring"),
                          p.uniformLocation("minMeters"),
                          p.uniformLocation("inverseRangeMeters"),
                          p.uniformLocation("shaderColours"),
                          p.uniformLocation("tint")};
    }
    Expected<gl::Program> splat = gl::Program::link(gl::kFullscreenVertexShader, kSplatFragmentShader);
    if (!splat)
        return Error{"splat shaders: " + splat.error().message};
    splatProgram_ = std::move(splat).value();
    glUseProgram(splatProgram_.id());
    glUniform1i(splatProgram_.uniformLocation("splatKeys"), 0);
    splatKeys_ = gl::Texture::create();
    Expected<gl::Program> anchors = gl::Program::link(kAnchorVertexShader, kPointColorFragmentShader);
    if (!anchors)
        return Error{"anchor shaders: " + anchors.error().message};
    anchorProgram_ = std::move(anchors).value();
    anchorViewProjection_ = anchorProgram_.uniformLocation("viewProjection");
    anchorPositions_ = anchorProgram_.uniformLocation("anchors");
    anchorHalfSize_ = anchorProgram_.uniformLocation("halfSize");
    emptyVertexArray_ = gl::VertexArray::create();
    glUseProgram(0);
    return Status::success();
}

void PointCloudRenderer::render(RenderTarget& target, const FrameTextures& textures,
                                const CloudParams& params, const CameraColours* camera) {
    lastPointCount_ = 0;
    if (target.empty())
        return;
    const RenderPass pass(target, params.background, true);
    if (params.accumulated) {
        params.accumulated->draw(params.worldToClip, params.pointSizePixels);
    } else if (const CloudProgram& cloud = programs_[static_cast<std::size_t>(params.colormap)];
               cloud.program && textures.hasDepth() && textures.depthIntrinsics().valid()) {
        glEnable(GL_PROGRAM_POINT_SIZE);
        glUseProgram(cloud.program.id());
        setUniforms(cloud.uniforms, textures, params, target);
        const bool shaded = camera && params.coloring == PointColoring::Camera;
        glUniform1i(cloud.uniforms.shaderColours, shaded ? 1 : 0);
        glUniform4f(cloud.uniforms.tint, 0.0f, 0.0f, 0.0f, 0.0f);
        if (shaded) {
            camera->setUniforms(cloud.program, textures);
            camera->bind();
        }
        textures.bind();
        glBindVertexArray(emptyVertexArray_.id());
        const GLsizei count = textures.depthWidth() * textures.depthHeight();
        glDrawArrays(GL_POINTS, 0, count);
        lastPointCount_ = static_cast<std::size_t>(count);
        drawLayers(cloud, params, target);
    }
    drawAnchors(params);
}

void PointCloudRenderer::drawLayers(const CloudProgram& cloud, const CloudParams& params,
                                    const RenderTarget& target) {
    for (const CloudLayer& layer : params.layers) {
        if (!layer.textures || !layer.textures->hasDepth() || !layer.textures->depthIntrinsics().valid())
            continue;
        CloudParams own = params;
        own.viewProjection = layer.viewProjection;
        own.minConfidence = layer.minConfidence.value_or(params.minConfidence);
        setUniforms(cloud.uniforms, *layer.textures, own, target);
        glUniform1i(cloud.uniforms.shaderColours, 0);
        glUniform4f(cloud.uniforms.tint, layer.tint.r, layer.tint.g, layer.tint.b, layer.tint.a);
        layer.textures->bind();
        const GLsizei count = layer.textures->depthWidth() * layer.textures->depthHeight();
        glDrawArrays(GL_POINTS, 0, count);
        lastPointCount_ += static_cast<std::size_t>(count);
    }
}

void PointCloudRenderer::renderSplat(RenderTarget& target, const CloudSplatter& splat,
                                     const CloudParams& params) {
    lastPointCount_ = splat.pointCount();
    if (target.empty())
        return;
    const bool fits = splat.width() == target.width() && splat.height() == target.height();
    if (fits && !splat.picture().empty()) {
        // The finished picture replaces the target's colour as it is: no pass, no clear. Nothing reads the
        // target's depth until a pass with anchors clears it again.
        glBindTexture(GL_TEXTURE_2D, target.colorTexture());
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, splat.width(), splat.height(), GL_RGBA, GL_UNSIGNED_BYTE,
                        splat.picture().data());
        return;
    }
    const RenderPass pass(target, params.background, true);
    if (fits && splatProgram_) {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, splatKeys_.id());
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        if (splatWidth_ != splat.width() || splatHeight_ != splat.height()) {
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RG32UI, splat.width(), splat.height(), 0, GL_RG_INTEGER,
                         GL_UNSIGNED_INT, splat.keys().data());
            splatWidth_ = splat.width();
            splatHeight_ = splat.height();
        } else {
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, splat.width(), splat.height(), GL_RG_INTEGER,
                            GL_UNSIGNED_INT, splat.keys().data());
        }
        glUseProgram(splatProgram_.id());
        glBindVertexArray(emptyVertexArray_.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    drawAnchors(params);
}

void PointCloudRenderer::drawAnchors(const CloudParams& params) const {
    if (!anchorProgram_ || params.anchors.empty())
        return;
    const auto count = static_cast<GLsizei>(std::min(params.anchors.size(), kMaxDrawnAnchors));
    glUseProgram(anchorProgram_.id());
    glUniformMatrix4fv(anchorViewProjection_, 1, GL_FALSE, glm::value_ptr(params.viewProjection));
    glUniform3fv(anchorPositions_, count, glm::value_ptr(params.anchors.front()));
    glUniform1f(anchorHalfSize_, 0.5f * params.anchorSizeMeters);
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArraysInstanced(GL_TRIANGLES, 0, 36, count);
}

void PointCloudRenderer::setUniforms(const Uniforms& u, const FrameTextures& textures,
                                     const CloudParams& params, const RenderTarget& target) const {
    const frame::Intrinsics& k = textures.depthIntrinsics();
    glUniformMatrix4fv(u.viewProjection, 1, GL_FALSE, glm::value_ptr(params.viewProjection));
    glUniform4f(u.depthIntrinsics, static_cast<float>(k.fx), static_cast<float>(k.fy),
                static_cast<float>(k.cx), static_cast<float>(k.cy));
    glUniform1ui(u.minConfidence, static_cast<GLuint>(params.minConfidence));
    glUniform1f(u.nearMeters, params.nearMeters);
    glUniform1f(u.pointSizePixels, params.pointSizePixels);
    glUniform1f(u.footprintPixels, footprintPixelsPerDepth(params, k, target.width(), target.height()));
    glUniform1i(u.coloring, static_cast<GLint>(params.coloring));
    glUniform1f(u.minMeters, params.rangeMinMeters);
    glUniform1f(u.inverseRangeMeters, 1.0f / std::max(params.rangeMaxMeters - params.rangeMinMeters, 1e-6f));
}

} // namespace dc::render
