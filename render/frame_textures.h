#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/shown_frame.h"
#include "render/gl_objects.h"

#include <cstdint>
#include <vector>

namespace dc::render {

namespace detail {
struct PlaneFormat; // the GL formats of one texture, private to frame_textures.cpp
} // namespace detail

// The shown depth as the textures the shaders read, one texel per point:
//   depth       GL_R32F,  meters, read with texelFetch; 0, negative, NaN and inf mean "no measurement"
//   confidence  GL_R8UI,  0 low / 1 medium / 2 high, read with texelFetch
//   colour      GL_RGB8,  the point's colour (the engine's point colours), read with texelFetch
// Textures are created on the first upload and reused while the sizes stay the same.
class FrameTextures {
public:
    // Texture units that bind() uses and connectSamplers() points a program's samplers at.
    static constexpr GLint kDepthUnit = 0;
    static constexpr GLint kConfidenceUnit = 1;
    static constexpr GLint kColorUnit = 2;

    // Depth and confidence of the shown depth (none: hasDepth() turns false). A map without confidence
    // gets all High, so nothing is filtered.
    void uploadDepth(const processing::ShownDepth& depth);
    // One colour per depth sample; null or of another size: mid-gray, as a frame without an image.
    void uploadColours(const processing::RgbImage* colours);
    // Binds the three textures to their units.
    void bind() const;
    // Sets the program's depthMap/confidenceMap/colorMap samplers to the units above; leaves the program
    // in use.
    static void connectSamplers(const gl::Program& program);

    bool hasDepth() const { return depth_.width > 0; }
    // False when the map had no confidence; the texture then holds all High so nothing is filtered.
    bool hasConfidence() const { return hasConfidence_; }
    int depthWidth() const { return depth_.width; }
    int depthHeight() const { return depth_.height; }
    // The intrinsics of the uploaded depth map.
    const frame::Intrinsics& depthIntrinsics() const { return depthIntrinsics_; }

    GLuint depthTexture() const { return depth_.texture.id(); }
    GLuint confidenceTexture() const { return confidence_.texture.id(); }
    GLuint colorTexture() const { return color_.texture.id(); }

private:
    struct PlaneTexture {
        gl::Texture texture;
        int width = 0;
        int height = 0;
    };
    static void uploadPlane(PlaneTexture& plane, const detail::PlaneFormat& format, int width, int height,
                            const void* pixels);

    PlaneTexture depth_;
    PlaneTexture confidence_;
    PlaneTexture color_;
    bool hasConfidence_ = false;
    frame::Intrinsics depthIntrinsics_;
    // Reused between frames: the all-High confidence map and the mid-gray colours.
    std::vector<std::uint8_t> confidenceScratch_;
    std::vector<std::uint8_t> grayScratch_;
};

// GLSL declaring the three samplers and the helpers every shader reading FrameTextures needs:
//   bool validDepth(float meters)    finite and positive
//   vec3 confidenceColor(uint level) low red, medium green, high blue
extern const char* const kFrameTexturesGlsl;

} // namespace dc::render
