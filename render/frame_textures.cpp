#include "render/frame_textures.h"

#include <utility>

namespace dc::render {

struct detail::PlaneFormat {
    GLint internalFormat;
    GLenum format;
    GLenum type;
};

namespace {

using detail::PlaneFormat;

// Every plane is read with texelFetch; integer formats are incomplete with linear filtering, so they are
// created through gl::bindNearestTexture like the rest.
constexpr PlaneFormat kDepthFormat{GL_R32F, GL_RED, GL_FLOAT};
constexpr PlaneFormat kConfidenceFormat{GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE};
constexpr PlaneFormat kColorFormat{GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE};

constexpr std::uint8_t kHighConfidence = static_cast<std::uint8_t>(frame::Confidence::High);
constexpr std::uint8_t kMidGray = 128; // frame::pixelRgb's colour without an image

// A depth map the shaders can index: non-empty, with as many samples as its size claims.
bool usable(const frame::Plane<float>& depth) {
    return depth.width > 0 && depth.height > 0 &&
           depth.pixels.size() == static_cast<std::size_t>(depth.width) * depth.height;
}

} // namespace

void FrameTextures::uploadDepth(const processing::ShownDepth& shown) {
    // Rows of R8 planes with odd widths are not 4-byte multiples, GL's default row alignment.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (!shown.data || !usable(shown.data->depthMeters)) {
        // hasDepth() reads the size, so forget it; the next map reallocates the storage.
        depth_.width = depth_.height = 0;
        hasConfidence_ = false;
        depthIntrinsics_ = {};
        return;
    }
    const frame::DepthData& depth = *shown.data;
    const int width = depth.depthMeters.width;
    const int height = depth.depthMeters.height;
    depthIntrinsics_ = shown.intrinsics;
    uploadPlane(depth_, kDepthFormat, width, height, depth.depthMeters.pixels.data());
    const frame::Plane<std::uint8_t>& confidence = depth.confidence;
    hasConfidence_ = confidence.width == width && confidence.height == height &&
                     confidence.pixels.size() == depth.depthMeters.pixels.size();
    if (hasConfidence_) {
        uploadPlane(confidence_, kConfidenceFormat, width, height, confidence.pixels.data());
        return;
    }
    confidenceScratch_.assign(depth.depthMeters.pixels.size(), kHighConfidence);
    uploadPlane(confidence_, kConfidenceFormat, width, height, confidenceScratch_.data());
}

void FrameTextures::uploadColours(const processing::RgbImage* colours) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const int width = std::max(depth_.width, 1), height = std::max(depth_.height, 1);
    if (colours && colours->width == depth_.width && colours->height == depth_.height && !colours->empty()) {
        uploadPlane(color_, kColorFormat, width, height, colours->pixels.data());
        return;
    }
    grayScratch_.assign(static_cast<std::size_t>(width) * height * 3, kMidGray);
    uploadPlane(color_, kColorFormat, width, height, grayScratch_.data());
}

void FrameTextures::uploadPlane(PlaneTexture& plane, const detail::PlaneFormat& format, int width, int height,
                                const void* pixels) {
    gl::bindNearestTexture(plane.texture);
    if (width == plane.width && height == plane.height) {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format.format, format.type, pixels);
        return;
    }
    glTexImage2D(GL_TEXTURE_2D, 0, format.internalFormat, width, height, 0, format.format, format.type,
                 pixels);
    plane.width = width;
    plane.height = height;
}

void FrameTextures::bind() const {
    gl::bindTextureUnits({{kDepthUnit, depth_.texture.id()},
                          {kConfidenceUnit, confidence_.texture.id()},
                          {kColorUnit, color_.texture.id()}});
}

void FrameTextures::connectSamplers(const gl::Program& program) {
    glUseProgram(program.id());
    glUniform1i(program.uniformLocation("depthMap"), kDepthUnit);
    glUniform1i(program.uniformLocation("confidenceMap"), kConfidenceUnit);
    glUniform1i(program.uniformLocation("colorMap"), kColorUnit);
}

const char* const kFrameTexturesGlsl = R"glsl(
uniform sampler2D depthMap;
uniform usampler2D confidenceMap;
uniform sampler2D colorMap;

// "No measurement" arrives as 0 from most sources, but NaN, inf and negative values from some.
bool validDepth(float meters) {
    return meters > 0.0 && !isinf(meters); // NaN fails the comparison
}

// The sample's confidence colours: low red, medium green, high blue.
vec3 confidenceColor(uint level) {
    return level == 0u ? vec3(1.0, 0.0, 0.0)
         : level == 1u ? vec3(0.0, 1.0, 0.0)
         : level == 2u ? vec3(0.0, 0.0, 1.0)
                       : vec3(0.0);
}
)glsl";

} // namespace dc::render
