#pragma once

#include "base/expected.h"
#include "frame/camera_model.h"
#include "frame/frame.h"
#include "processing/registration.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/gl_objects.h"
#include "render/render_target.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::render {

// The camera's colours of the cloud's points made on the GPU, as the Depth Cloud sample does: the camera
// image's own planes are uploaded unconverted (NV12 as Y and CbCr, YUYV as pixel pairs, RGB as is) and the
// point shader converts the pixel a point lands on with frame::ycbcrToRgb's matrix. With one camera a sample
// takes the pixel processing::cameraPixelOf gives; with a two-sensor rig it is projected into the colour
// camera as processing::registerDepth projects it, and a depth-only pass into the colour camera's view (a
// shadow map: each sample a square of its footprint) says which samples a nearer surface hides, so they stay
// gray. The results equal processing::framePointColours' up to rounding.
//
// Lives on the GL thread with a context current.
class CameraColours {
public:
    // Texture units of the camera planes and of the colour camera's nearest-depth map, after FrameTextures'.
    static constexpr GLint kLumaUnit = 3;
    static constexpr GLint kChromaUnit = 4;
    static constexpr GLint kNearestUnit = 5;

    Status init();
    // Uploads the image's planes unless they are the ones uploaded last; an empty or undecodable image
    // colours every point mid-gray, as frame::pixelRgb does.
    void uploadImage(const frame::CapturedImage& image);
    // The rig the points are registered through; null or a single camera: none.
    void setRig(std::shared_ptr<const frame::RigCalibration> rig);
    // With a rig, draws the samples of `textures` into the colour camera's view (the nearest depth per
    // colour pixel). Changes the bound framebuffer and viewport.
    void renderNearest(const FrameTextures& textures);
    // The camera panel's picture: the uploaded image in RGB at width x height, each pixel the area average of
    // the image pixels it covers (as processing::cameraRgbImage resizes), top row at the target's top.
    void renderImage(RenderTarget& target, int width, int height);
    // The depth panel's colour overlay (processing::seenColourOverlay) at the size the panel is drawn: one
    // pixel per step x step cell of `whole` (the shown depth map undecimated), each the colour of the sample
    // processing::sampleCellCentres keeps, opaque where the colour camera sees it and transparent where it
    // does not (with a rig, after a visibility pass of every sample of `whole`). Changes the bound
    // framebuffer and viewport.
    void renderSeenColours(RenderTarget& target, const FrameTextures& whole, int step);
    // The depth over the camera of a two-sensor frame: the samples of `textures` drawn into the colour
    // camera's view at width x height, each pixel the nearest sample covering it (processing::
    // alignDepthToColour) in `colours`, transparent where none does. The target needs a depth buffer.
    struct AlignedColours {
        float minMeters = 0.0f;
        float maxMeters = 1.0f;
        Colormap colormap = Colormap::Jet;
    };
    void renderAlignedDepth(RenderTarget& target, const FrameTextures& textures, int width, int height,
                            const AlignedColours& colours);
    // Binds the planes and the nearest-depth map to their units.
    void bind() const;
    // Sets a point program's uniforms (kCameraColoursGlsl) for the samples of `textures`; the program must
    // be in use.
    void setUniforms(const gl::Program& program, const FrameTextures& textures) const;
    // Points the samplers of a program that includes kCameraColoursGlsl at the units above; leaves it in use.
    static void connectSamplers(const gl::Program& program);

    bool registers() const { return rig_ != nullptr; }
    // Plane uploads and visibility passes so far: tests count work.
    std::uint64_t uploads() const { return uploads_; }
    std::uint64_t nearestPasses() const { return nearestPasses_; }
    std::uint64_t imagePasses() const { return imagePasses_; }
    std::uint64_t seenPasses() const { return seenPasses_; }
    std::uint64_t alignedPasses() const { return alignedPasses_; }
    // Whether an image is uploaded (and what renderImage draws is a picture).
    bool hasImage() const { return format_ != 0; }

private:
    struct Plane {
        gl::Texture texture;
        int width = 0;
        int height = 0;
    };
    void uploadPlane(Plane& plane, GLint internalFormat, GLenum format, int width, int height,
                     const void* pixels);
    // The projection of the current rig for a depth map with these intrinsics, recomputed when they change.
    const processing::ColourProjection& projection(const frame::Intrinsics& depthIntrinsics) const;
    int marginPixels(const frame::Intrinsics& depthIntrinsics) const;
    // The registration uniforms of kCameraColoursGlsl for projection p; the program must be in use.
    static void setProjection(const gl::Program& program, const processing::ColourProjection& p);
    Status linkAlignedPrograms(const std::string& vertexShader);

    Plane luma_;     // NV12: Y (R8); YUYV: one texel per pixel pair, Y0 Cb Y1 Cr (RGBA8); RGB: RGB8
    Plane chroma_;   // NV12: CbCr (RG8), one texel per 2x2 pixels
    int format_ = 0; // as the shader's cameraFormat: 0 none, 1 NV12, 2 YUYV, 3 RGB
    int width_ = 0, height_ = 0;
    std::shared_ptr<const std::vector<std::uint8_t>> uploadedBytes_;
    std::shared_ptr<const frame::RigCalibration> rig_;
    mutable std::optional<std::pair<frame::Intrinsics, processing::ColourProjection>> projection_;
    gl::Program nearestProgram_;
    gl::Program imageProgram_;
    gl::Program seenProgram_;
    std::array<gl::Program, kColormapCount> alignedPrograms_;
    gl::Framebuffer nearestFramebuffer_;
    Plane nearest_; // GL_DEPTH_COMPONENT32F, the camera image's size plus a margin on every side
    gl::VertexArray emptyVertexArray_;
    std::uint64_t uploads_ = 0;
    std::uint64_t nearestPasses_ = 0;
    std::uint64_t imagePasses_ = 0;
    std::uint64_t seenPasses_ = 0;
    std::uint64_t alignedPasses_ = 0;
};

// GLSL for a point vertex shader that includes kFrameTexturesGlsl first:
//   vec3 cameraPointColor(ivec2 pixel, ivec2 mapSize, vec3 point)
// the camera's colour of depth sample `pixel` of a mapSize map, at `point` of the depth camera's frame;
//   vec4 seenCameraColor(ivec2 pixel, ivec2 mapSize, vec3 point)
// the same with alpha 1 where the colour camera sees the sample and 0 where it does not.
extern const char* const kCameraColoursGlsl;

} // namespace dc::render
