#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/shown_frame.h"
#include "render/accumulated_points.h"
#include "render/camera_colours.h"
#include "render/cloud_splat.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/gl_objects.h"
#include "render/render_target.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace dc::render {

// What gives each point its colour: the camera image (the sample's look), the depth through the depth
// panel's colormap and range, or the confidence level as the confidence panel shows it.
enum class PointColoring { Camera, Depth, Confidence };
inline constexpr int kPointColoringCount = 3;
const char* toString(PointColoring coloring);

// Another camera's samples drawn into the same cloud (several sources fused in one world): its samples
// (and their textures, for GL points), where its camera sits in the view, and a tint that colours every one
// of its points.
struct CloudLayer {
    const FrameTextures* textures = nullptr;
    // Maps a point of this layer's camera frame to clip space.
    glm::mat4 viewProjection{1.0f};
    glm::vec4 tint{0.0f}; // rgb, and a > 0 to use it instead of the point's own colour
    // The samples: what the textures hold on the GPU path (so that a drawing of other samples is not taken
    // for this one), what the CPU splat reads.
    std::shared_ptr<const frame::DepthData> depth;
    frame::Intrinsics intrinsics;
    std::shared_ptr<const processing::RgbImage> colours;
    std::optional<frame::Confidence> minConfidence; // its own level; none: the cloud's

    bool operator==(const CloudLayer&) const = default;
};

struct CloudParams {
    // Maps a point of the depth camera's frame (OpenCV axes: x right, y down, z forward; meters) to clip
    // space, e.g. cloudViewProjection() of orbit_camera.h.
    glm::mat4 viewProjection{1.0f};
    // Samples below this level are not drawn (the sample's confidence selection).
    frame::Confidence minConfidence = frame::Confidence::Low;
    // Samples closer than this are not drawn, like the sample's fragment shader does below 1 m.
    float nearMeters = 0.1f;
    float pointSizePixels = 2.0f;
    // Points at least as wide as their sample's footprint on screen (a depth pixel at depth z spans z / f
    // meters), so a surface seen from near the depth camera shows no background between its samples.
    bool fillGaps = false;
    PointColoring coloring = PointColoring::Camera;
    Colormap colormap = Colormap::Jet; // PointColoring::Depth, over [rangeMinMeters, rangeMaxMeters]
    float rangeMinMeters = 0.0f;
    float rangeMaxMeters = 2.5f;
    glm::vec3 background{0.0f, 0.0f, 0.0f}; // linear RGB in [0, 1]
    // Anchors, in the same frame as the points, drawn as small lit cubes among them (depth-tested).
    std::vector<glm::vec3> anchors;
    float anchorSizeMeters = 0.012f;
    // Accumulate mode: these world points are drawn instead of the frame's own, through worldToClip
    // (viewProjection composed with the current frame's world-to-camera transform).
    const AccumulatedPoints* accumulated = nullptr;
    glm::mat4 worldToClip{1.0f};
    // Drawn with the frame's own samples, each through its own matrix.
    std::vector<CloudLayer> layers;

    bool operator==(const CloudParams&) const = default;
};

inline constexpr std::size_t kMaxDrawnAnchors = 32;
// The widest a point grows to fill gaps: beyond it the view is so close that a sample is a blob anyway.
inline constexpr float kMaxFillPixels = 32.0f;

// With params.fillGaps, the footprint in pixels of a sample of a map with intrinsics `k`, per meter of its
// depth over its distance from the viewer (clip w): a point at depth z and clip w spans z / w times this. 0
// without fillGaps.
float footprintPixelsPerDepth(const CloudParams& params, const frame::Intrinsics& k, int width, int height);

// Draws one point per depth sample, placed by unprojecting it through the depth intrinsics and coloured
// as CloudParams says (by default the camera's colour, the Depth Cloud sample's pointCloudVertexShader). All
// the work happens in the vertex shader: no vertex buffer, one vertex per depth pixel addressed by
// gl_VertexID.
class PointCloudRenderer {
public:
    // Compiles the shaders; needs a current context.
    Status init();
    // Clears `target` to the background and draws the cloud; draws nothing without depth or with invalid
    // intrinsics. Camera-coloured points take their colours from `camera` when given (its nearest-depth
    // pass already drawn for these textures), else from the textures' colour plane. Leaves framebuffer 0
    // bound.
    void render(RenderTarget& target, const FrameTextures& textures, const CloudParams& params,
                const CameraColours* camera = nullptr);
    // Shows a cloud splatted on the CPU (its size must be the target's): its finished picture uploaded
    // as the target's colour, or, when it left keys for a pass, clears `target`, draws them and the
    // anchors depth-tested among its points and leaves framebuffer 0 bound.
    void renderSplat(RenderTarget& target, const CloudSplatter& splat, const CloudParams& params);
    // Vertices submitted by the last render(): every depth sample, culled ones included.
    std::size_t lastPointCount() const { return lastPointCount_; }

private:
    struct Uniforms {
        GLint viewProjection = -1;
        GLint depthIntrinsics = -1;
        GLint minConfidence = -1;
        GLint nearMeters = -1;
        GLint pointSizePixels = -1;
        GLint footprintPixels = -1;
        GLint coloring = -1;
        GLint minMeters = -1;
        GLint inverseRangeMeters = -1;
        GLint shaderColours = -1;
        GLint tint = -1;
    };
    // A cloud program per colormap (colormapGlsl says why), with its uniforms.
    struct CloudProgram {
        gl::Program program;
        Uniforms uniforms;
    };

    void setUniforms(const Uniforms& uniforms, const FrameTextures& textures, const CloudParams& params,
                     const RenderTarget& target) const;
    void drawAnchors(const CloudParams& params) const;
    void drawLayers(const CloudProgram& cloud, const CloudParams& params, const RenderTarget& target);

    std::array<CloudProgram, kColormapCount> programs_;
    gl::Program splatProgram_;
    gl::Texture splatKeys_; // CloudSplatter's keys as GL_RG32UI: colour, window depth bits
    int splatWidth_ = 0;
    int splatHeight_ = 0;
    gl::Program anchorProgram_;
    GLint anchorViewProjection_ = -1;
    GLint anchorPositions_ = -1;
    GLint anchorHalfSize_ = -1;
    gl::VertexArray emptyVertexArray_; // core profile draws need a bound VAO even without attributes
    std::size_t lastPointCount_ = 0;
};

} // namespace dc::render
