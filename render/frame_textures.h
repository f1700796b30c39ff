#pragma once

#include "frame/frame.h"
#include "render/gl_objects.h"

#include <cstdint>
#include <vector>

namespace dc::render {

namespace detail {
struct PlaneFormat; // the GL formats of one texture, private to frame_textures.cpp
} // namespace detail

// One frame's data as the textures the shaders read, laid out like the Depth Cloud sample's:
//   depth       GL_R32F,  meters, read with texelFetch; 0, negative, NaN and inf mean "no measurement"
//   confidence  GL_R8UI,  0 low / 1 medium / 2 high, read with texelFetch
//   luma        GL_R8,    full-range Y of the camera image, sampled with linear filtering
//   chroma      GL_RG8,   Cb and Cr (centred on 0.5), at whatever resolution the format subsamples to
// Textures are created on the first upload and reused while the sizes stay the same.
class FrameTextures {
public:
    // Texture units that bind() uses and connectSamplers() points a program's samplers at.
    static constexpr GLint kDepthUnit = 0;
    static constexpr GLint kConfidenceUnit = 1;
    static constexpr GLint kLumaUnit = 2;
    static constexpr GLint kChromaUnit = 3;

    // Uses the frame's smoothedSceneDepth when asked for and present, otherwise its sceneDepth. Every camera
    // format is uploaded as luma + chroma: NV12 directly, YUYV and RGB24 converted on the CPU. A frame
    // without an image (or with a malformed one) gets a mid-gray 1x1 image.
    void upload(const frame::Frame& frame, bool preferSmoothed);
    // Binds the four textures to their units.
    void bind() const;
    // Sets the program's depthMap/confidenceMap/lumaMap/chromaMap samplers to the units above; leaves the
    // program in use.
    static void connectSamplers(const gl::Program& program);

    bool hasDepth() const { return depth_.width > 0; }
    // False when the frame had no confidence map; the texture then holds all High so nothing is filtered.
    bool hasConfidence() const { return hasConfidence_; }
    bool hasCameraImage() const { return cameraWidth_ > 0; }
    int depthWidth() const { return depth_.width; }
    int depthHeight() const { return depth_.height; }
    int cameraWidth() const { return cameraWidth_; }
    int cameraHeight() const { return cameraHeight_; }
    // The camera intrinsics scaled to the uploaded depth map (Frame::depthIntrinsics() for sceneDepth).
    const frame::Intrinsics& depthIntrinsics() const { return depthIntrinsics_; }

    GLuint depthTexture() const { return depth_.texture.id(); }
    GLuint confidenceTexture() const { return confidence_.texture.id(); }
    GLuint lumaTexture() const { return luma_.texture.id(); }
    GLuint chromaTexture() const { return chroma_.texture.id(); }

private:
    struct PlaneTexture {
        gl::Texture texture;
        int width = 0;
        int height = 0;
    };
    static void uploadPlane(PlaneTexture& plane, const detail::PlaneFormat& format, int width, int height,
                            const void* pixels);
    void uploadDepth(const frame::DepthData* depth, const frame::Intrinsics& cameraIntrinsics);
    void uploadCamera(const frame::CapturedImage& image);

    PlaneTexture depth_;
    PlaneTexture confidence_;
    PlaneTexture luma_;
    PlaneTexture chroma_;
    bool hasConfidence_ = false;
    int cameraWidth_ = 0;
    int cameraHeight_ = 0;
    frame::Intrinsics depthIntrinsics_;
    // Reused between frames: the all-High confidence map and the planes of converted camera images.
    std::vector<std::uint8_t> confidenceScratch_;
    std::vector<std::uint8_t> lumaScratch_;
    std::vector<std::uint8_t> chromaScratch_;
};

// GLSL declaring the four samplers and the helpers every shader reading FrameTextures needs:
//   bool validDepth(float meters)  finite and positive
//   vec3 cameraColor(vec2 uv)      the camera image at uv ((0, 0) top-left), full-range BT.601 to RGB
extern const char* const kFrameTexturesGlsl;

} // namespace dc::render
