#include "render/frame_textures.h"

#include "frame/color.h"

#include <utility>

namespace dc::render {

struct detail::PlaneFormat {
    GLint internalFormat;
    GLenum format;
    GLenum type;
    GLint filter;
};

namespace {

using detail::PlaneFormat;

// Depth and confidence are read with texelFetch, which ignores filtering, but a texture must still be
// complete to be read at all: integer formats are incomplete with linear filtering, and so is any texture
// left with the default minification filter, which expects mipmaps.
constexpr PlaneFormat kDepthFormat{GL_R32F, GL_RED, GL_FLOAT, GL_NEAREST};
constexpr PlaneFormat kConfidenceFormat{GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, GL_NEAREST};
constexpr PlaneFormat kLumaFormat{GL_R8, GL_RED, GL_UNSIGNED_BYTE, GL_LINEAR};
constexpr PlaneFormat kChromaFormat{GL_RG8, GL_RG, GL_UNSIGNED_BYTE, GL_LINEAR};

constexpr std::uint8_t kHighConfidence = static_cast<std::uint8_t>(frame::Confidence::High);
constexpr std::uint8_t kMidGray = 128;              // Y = 0.5 and neutral chroma: mid-gray
constexpr std::uint8_t kGrayChroma[2] = {128, 128}; // Cb = Cr = 0.5: no color

// A camera image as the shaders' two planes; the chroma size is whatever the format subsamples to.
struct YcbcrPlanes {
    const std::uint8_t* luma;
    const std::uint8_t* chroma;
    int chromaWidth;
    int chromaHeight;
};

// A known format with positive size and at least the bytes it needs (byteSize() is 0 for unknown formats).
bool wellFormed(const frame::CapturedImage& image) {
    if (image.empty() || image.width <= 0 || image.height <= 0)
        return false;
    const std::size_t needed = frame::CapturedImage::byteSize(image.format, image.width, image.height);
    return needed > 0 && image.bytes->size() >= needed;
}

// YUYV carries one Cb/Cr pair per horizontal pixel pair: chroma at half width, full height.
void splitYuyv(const frame::CapturedImage& image, std::vector<std::uint8_t>& luma,
               std::vector<std::uint8_t>& chroma) {
    const int pairs = (image.width + 1) / 2;
    luma.resize(static_cast<std::size_t>(image.width) * image.height);
    chroma.resize(static_cast<std::size_t>(pairs) * 2 * image.height);
    const std::uint8_t* source = image.bytes->data();
    for (int y = 0; y < image.height; ++y) {
        const std::uint8_t* row = source + static_cast<std::size_t>(y) * pairs * 4;
        std::uint8_t* lumaRow = luma.data() + static_cast<std::size_t>(y) * image.width;
        std::uint8_t* chromaRow = chroma.data() + static_cast<std::size_t>(y) * pairs * 2;
        for (int x = 0; x < image.width; ++x)
            lumaRow[x] = row[x * 2];
        for (int pair = 0; pair < pairs; ++pair) {
            chromaRow[pair * 2] = row[pair * 4 + 1];
            chromaRow[pair * 2 + 1] = row[pair * 4 + 3];
        }
    }
}

// RGB is converted to full-resolution YCbCr so every format takes the shaders' one color path. The
// round trip through 8-bit YCbCr costs about 1/255 per channel.
void convertRgb24(const frame::CapturedImage& image, std::vector<std::uint8_t>& luma,
                  std::vector<std::uint8_t>& chroma) {
    const std::size_t count = static_cast<std::size_t>(image.width) * image.height;
    luma.resize(count);
    chroma.resize(count * 2);
    const std::uint8_t* rgb = image.bytes->data();
    for (std::size_t i = 0; i < count; ++i) {
        const frame::Rgb color{rgb[i * 3] / 255.0f, rgb[i * 3 + 1] / 255.0f, rgb[i * 3 + 2] / 255.0f};
        const frame::Ycbcr ycbcr = frame::rgbToYcbcr(color);
        luma[i] = frame::toByte(ycbcr.y);
        chroma[i * 2] = frame::toByte(ycbcr.cb);
        chroma[i * 2 + 1] = frame::toByte(ycbcr.cr);
    }
}

YcbcrPlanes ycbcrPlanes(const frame::CapturedImage& image, std::vector<std::uint8_t>& lumaScratch,
                        std::vector<std::uint8_t>& chromaScratch) {
    const std::uint8_t* bytes = image.bytes->data();
    switch (image.format) {
    case frame::PixelFormat::Nv12: // already the shaders' layout: upload the planes in place
        return {bytes, bytes + static_cast<std::size_t>(image.width) * image.height, (image.width + 1) / 2,
                (image.height + 1) / 2};
    case frame::PixelFormat::Yuyv:
        splitYuyv(image, lumaScratch, chromaScratch);
        return {lumaScratch.data(), chromaScratch.data(), (image.width + 1) / 2, image.height};
    case frame::PixelFormat::Rgb24:
        convertRgb24(image, lumaScratch, chromaScratch);
        return {lumaScratch.data(), chromaScratch.data(), image.width, image.height};
    }
    return {nullptr, nullptr, 0, 0}; // unreachable: wellFormed() rejects unknown formats
}

// A depth map the shaders can index: non-empty, with as many samples as its size claims.
bool usable(const frame::Plane<float>& depth) {
    return depth.width > 0 && depth.height > 0 &&
           depth.pixels.size() == static_cast<std::size_t>(depth.width) * depth.height;
}

} // namespace

void FrameTextures::upload(const frame::Frame& frame, bool preferSmoothed) {
    // Rows of R8 and RG8 planes with odd widths are not 4-byte multiples, GL's default row alignment.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const bool smoothed = preferSmoothed && frame.smoothedSceneDepth.has_value();
    const std::optional<frame::DepthData>& depth = smoothed ? frame.smoothedSceneDepth : frame.sceneDepth;
    uploadDepth(depth ? &*depth : nullptr, frame.cameraIntrinsics);
    uploadCamera(frame.capturedImage);
}

void FrameTextures::uploadDepth(const frame::DepthData* depth, const frame::Intrinsics& cameraIntrinsics) {
    if (!depth || !usable(depth->depthMeters)) {
        // hasDepth() reads the size, so forget it; the next frame with depth reallocates the storage.
        depth_.width = depth_.height = 0;
        hasConfidence_ = false;
        depthIntrinsics_ = {};
        return;
    }
    const int width = depth->depthMeters.width;
    const int height = depth->depthMeters.height;
    // Scaled to the map actually uploaded, which for smoothed depth need not match sceneDepth's size.
    depthIntrinsics_ = cameraIntrinsics.scaledTo(width, height);
    uploadPlane(depth_, kDepthFormat, width, height, depth->depthMeters.pixels.data());

    const frame::Plane<std::uint8_t>& confidence = depth->confidence;
    hasConfidence_ = confidence.width == width && confidence.height == height &&
                     confidence.pixels.size() == depth->depthMeters.pixels.size();
    if (hasConfidence_) {
        uploadPlane(confidence_, kConfidenceFormat, width, height, confidence.pixels.data());
        return;
    }
    confidenceScratch_.assign(depth->depthMeters.pixels.size(), kHighConfidence);
    uploadPlane(confidence_, kConfidenceFormat, width, height, confidenceScratch_.data());
}

void FrameTextures::uploadCamera(const frame::CapturedImage& image) {
    if (!wellFormed(image)) {
        cameraWidth_ = cameraHeight_ = 0;
        uploadPlane(luma_, kLumaFormat, 1, 1, &kMidGray);
        uploadPlane(chroma_, kChromaFormat, 1, 1, kGrayChroma);
        return;
    }
    cameraWidth_ = image.width;
    cameraHeight_ = image.height;
    const YcbcrPlanes planes = ycbcrPlanes(image, lumaScratch_, chromaScratch_);
    uploadPlane(luma_, kLumaFormat, image.width, image.height, planes.luma);
    uploadPlane(chroma_, kChromaFormat, planes.chromaWidth, planes.chromaHeight, planes.chroma);
}

void FrameTextures::uploadPlane(PlaneTexture& plane, const detail::PlaneFormat& format, int width, int height,
                                const void* pixels) {
    if (!plane.texture) {
        plane.texture = gl::Texture::create();
        glBindTexture(GL_TEXTURE_2D, plane.texture.id());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, format.filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, format.filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    } else {
        glBindTexture(GL_TEXTURE_2D, plane.texture.id());
    }
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
    const std::pair<GLint, GLuint> bindings[] = {{kDepthUnit, depth_.texture.id()},
                                                 {kConfidenceUnit, confidence_.texture.id()},
                                                 {kLumaUnit, luma_.texture.id()},
                                                 {kChromaUnit, chroma_.texture.id()}};
    for (const auto& [unit, texture] : bindings) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, texture);
    }
    glActiveTexture(GL_TEXTURE0);
}

void FrameTextures::connectSamplers(const gl::Program& program) {
    glUseProgram(program.id());
    glUniform1i(program.uniformLocation("depthMap"), kDepthUnit);
    glUniform1i(program.uniformLocation("confidenceMap"), kConfidenceUnit);
    glUniform1i(program.uniformLocation("lumaMap"), kLumaUnit);
    glUniform1i(program.uniformLocation("chromaMap"), kChromaUnit);
}

const char* const kFrameTexturesGlsl = R"glsl(
uniform sampler2D depthMap;
uniform usampler2D confidenceMap;
uniform sampler2D lumaMap;
uniform sampler2D chromaMap;

// "No measurement" arrives as 0 from most sources, but NaN, inf and negative values from some.
bool validDepth(float meters) {
    return meters > 0.0 && !isinf(meters); // NaN fails the comparison
}

// Full-range BT.601 with the coefficients of frame::ycbcrToRgb (and of the Depth Cloud sample).
vec3 cameraColor(vec2 uv) {
    float y = texture(lumaMap, uv).r;
    vec2 c = texture(chromaMap, uv).rg - 0.5;
    return vec3(y + 1.402 * c.y, y - 0.3441 * c.x - 0.7141 * c.y, y + 1.772 * c.x);
}
)glsl";

} // namespace dc::render
