#include "render/camera_colours.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dc::render {

namespace {

void setDepthIntrinsics(const gl::Program& program, const FrameTextures& textures) {
    const frame::Intrinsics& k = textures.depthIntrinsics();
    glUniform4f(program.uniformLocation("depthIntrinsics"), static_cast<float>(k.fx),
                static_cast<float>(k.fy), static_cast<float>(k.cx), static_cast<float>(k.cy));
}

// Points drawn into a depth buffer where the nearest sample over a pixel is the one kept.
void nearestPointWinsState() {
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
}

constexpr int kFormatNone = 0, kFormatNv12 = 1, kFormatYuyv = 2, kFormatRgb = 3;

// Draws every sample with depth as a square of its footprint into the colour camera's view, at the depth
// along the colour camera's axis (kNearestFarMeters is depth 1): the depth buffer then holds the nearest
// surface over each colour pixel, as registerDepth's z-buffer does.
constexpr const char* kNearestVertexMain = R"glsl(
uniform vec4 depthIntrinsics; // fx, fy, cx, cy in depth-map pixels
flat out float colourZMeters; // what the aligned depth's fragments colour
flat out vec3 colourSquare;   // the sample's position in the colour image and its square's half side, pixels
// The aligned depth's pass: image row 0 at the target's top (RenderTarget's pictures), not at GL's y = 0,
// and each point a pixel wider on every side, its fragment shader keeping exactly the pixels of its square.
uniform bool topDown;

void main() {
    ivec2 size = textureSize(depthMap, 0);
    ivec2 pixel = ivec2(gl_VertexID % size.x, gl_VertexID / size.x);
    float z = texelFetch(depthMap, pixel, 0).r;
    vec3 c = validDepth(z)
                 ? toColourImage(vec3((vec2(pixel) - depthIntrinsics.zw) * z / depthIntrinsics.xy, z))
                 : vec3(0.0);
    gl_PointSize = 1.0;
    if (!(c.z > 0.0) || c.z >= kNearestFarMeters) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // clipped
        return;
    }
    colourZMeters = c.z;
    float halfSide = clamp(halfPerDepthOverColourZ * z / c.z, 0.5, 16384.0);
    colourSquare = vec3(c.xy, halfSide);
    gl_PointSize = 2.0 * halfSide + (topDown ? 2.0 : 0.0);
    // Pixel centres of the colour image sit at integers, GL's at half integers; the view has a margin
    // on every side so that samples just outside the image still cover its border pixels.
    vec2 window = c.xy + 0.5 + float(nearestMargin);
    if (topDown)
        window.y = float(cameraSize.y + 2 * nearestMargin) - window.y;
    gl_Position = vec4(window / vec2(cameraSize + 2 * nearestMargin) * 2.0 - 1.0,
                       c.z / kNearestFarMeters * 2.0 - 1.0, 1.0);
}
)glsl";

constexpr const char* kDepthOnlyFragmentShader = R"glsl(#version 330 core
void main() {
}
)glsl";

// The nearest sample over each pixel of the colour camera's view, in the depth panel's colormap. A sample
// covers the pixels of its square as registerDepth's z-buffer rounds them (ceil to floor): the rasteriser's
// own rule, applied to positions snapped to its subpixel grid, gave a neighbouring sample's depth on a few
// pixels in a thousand.
constexpr const char* kAlignedFragmentMain = R"glsl(
flat in float colourZMeters;
flat in vec3 colourSquare;
uniform float minMeters;
uniform float inverseRangeMeters;
uniform int outputHeight;
out vec4 fragColor;

void main() {
    vec2 pixel = vec2(floor(gl_FragCoord.x), float(outputHeight - 1) - floor(gl_FragCoord.y));
    if (any(lessThan(pixel, ceil(colourSquare.xy - colourSquare.z))) ||
        any(greaterThan(pixel, floor(colourSquare.xy + colourSquare.z))))
        discard;
    fragColor = vec4(colormapColor((colourZMeters - minMeters) * inverseRangeMeters), 1.0);
}
)glsl";

// One pixel per shown cell of the depth panel, which shows sample processing::sampleCellCentres keeps of
// each step x step cell: that sample of the whole map is coloured, so that visibility is decided against
// every sample as framePointColours decides it. A registered sample without depth lands nowhere.
constexpr const char* kSeenColoursFragmentMain = R"glsl(
uniform vec4 depthIntrinsics; // of the whole map
uniform int sampleStep;
uniform ivec2 outputSize;
out vec4 fragColor;

void main() {
    ivec2 mapSize = textureSize(depthMap, 0);
    ivec2 cell = ivec2(int(gl_FragCoord.x), outputSize.y - 1 - int(gl_FragCoord.y));
    ivec2 pixel = min(cell * sampleStep + sampleStep / 2, mapSize - 1);
    float z = texelFetch(depthMap, pixel, 0).r;
    if (registered && !validDepth(z)) {
        fragColor = vec4(0.0);
        return;
    }
    vec3 point = vec3((vec2(pixel) - depthIntrinsics.zw) * z / depthIntrinsics.xy, z);
    vec4 colour = seenCameraColor(pixel, mapSize, point);
    fragColor = colour.a > 0.0 ? colour : vec4(0.0);
}
)glsl";

// Each output pixel averages the image pixels it covers, weighted by the area they share (a box filter,
// exact at any scale), in YCbCr (or RGB), then converts: the conversion is linear, so this is the average
// of the converted pixels up to the clamp.
constexpr const char* kImageFragmentMain = R"glsl(
uniform ivec2 outputSize;
out vec4 fragColor;

vec3 cameraValue(ivec2 p) {
    if (cameraFormat == 1)
        return vec3(texelFetch(cameraLuma, p, 0).r, texelFetch(cameraChroma, p / 2, 0).rg);
    if (cameraFormat == 2) {
        vec4 pair = texelFetch(cameraLuma, ivec2(p.x / 2, p.y), 0);
        return vec3((p.x & 1) == 0 ? pair.r : pair.b, pair.g, pair.a);
    }
    return texelFetch(cameraLuma, p, 0).rgb;
}

void main() {
    ivec2 o = ivec2(int(gl_FragCoord.x), outputSize.y - 1 - int(gl_FragCoord.y));
    vec2 scale = vec2(cameraSize) / vec2(outputSize);
    vec2 low = vec2(o) * scale;
    vec2 high = vec2(o + 1) * scale;
    vec3 sum = vec3(0.0);
    float total = 0.0;
    for (int y = int(floor(low.y)); y < int(ceil(high.y)); ++y) {
        float wy = min(high.y, float(y + 1)) - max(low.y, float(y));
        for (int x = int(floor(low.x)); x < int(ceil(high.x)); ++x) {
            float w = wy * (min(high.x, float(x + 1)) - max(low.x, float(x)));
            sum += w * cameraValue(ivec2(x, y));
            total += w;
        }
    }
    vec3 value = sum / total;
    fragColor = vec4(clamp(cameraFormat == 3 ? value : ycbcrToRgb(value), 0.0, 1.0), 1.0);
}
)glsl";

bool usableImage(const frame::CapturedImage& image) {
    return !image.empty() && image.raw() && image.width > 0 && image.height > 0 &&
           image.bytes->size() >= frame::CapturedImage::byteSize(image.format, image.width, image.height);
}

// Thinner than any depth range worth showing, as PanelRenderer's; keeps a collapsed range finite.
constexpr float kMinRangeMeters = 1e-6f;

float finiteOrMax(double v) {
    return std::isfinite(v) ? static_cast<float>(v) : std::numeric_limits<float>::max();
}

} // namespace

const char* const kCameraColoursGlsl = R"glsl(
uniform sampler2D cameraLuma;
uniform sampler2D cameraChroma;
uniform sampler2D colourNearest; // the nearest depth over each colour pixel, / kNearestFarMeters
uniform int cameraFormat;        // 0 none, 1 NV12, 2 YUYV, 3 RGB
uniform ivec2 cameraSize;
uniform bool registered;         // a two-sensor rig: project into the colour camera, test visibility
uniform mat3 depthToColourRotation;
uniform vec3 depthToColourTranslation;
uniform vec4 colourIntrinsics;   // fx, fy, cx, cy at the camera image's size
uniform float colourLens[5];     // k1 k2 p1 p2 k3 (Brown-Conrady, forward); all 0 for a pinhole
uniform float colourMaxRadius2;
uniform float colourMarginPixels;
uniform float halfPerDepthOverColourZ;
uniform int nearestMargin;

const float kNearestFarMeters = 1024.0;
const float kUnseenGray = 128.0 / 255.0; // processing::kUnseenGray, frame::pixelRgb's mid-gray in bytes

// frame::ycbcrToRgb: full-range BT.601, the Depth Cloud sample's matrix.
vec3 ycbcrToRgb(vec3 c) {
    float cb = c.y - 0.5;
    float cr = c.z - 0.5;
    return vec3(c.x + 1.402 * cr, c.x - 0.3441 * cb - 0.7141 * cr, c.x + 1.772 * cb);
}

vec3 cameraRgb(ivec2 p) {
    p = clamp(p, ivec2(0), cameraSize - 1);
    if (cameraFormat == 1)
        return ycbcrToRgb(vec3(texelFetch(cameraLuma, p, 0).r, texelFetch(cameraChroma, p / 2, 0).rg));
    if (cameraFormat == 2) {
        vec4 pair = texelFetch(cameraLuma, ivec2(p.x / 2, p.y), 0);
        return ycbcrToRgb(vec3((p.x & 1) == 0 ? pair.r : pair.b, pair.g, pair.a));
    }
    if (cameraFormat == 3)
        return texelFetch(cameraLuma, p, 0).rgb;
    return vec3(kUnseenGray);
}

// Where point p of the depth camera's frame lands in the colour image, as processing::registerDepth
// projects it: (x, y) in pixels with centres at integers, z the depth along the colour camera's axis;
// z = 0 where it lands nowhere near the image.
vec3 toColourImage(vec3 p) {
    vec3 q = depthToColourRotation * p + depthToColourTranslation;
    float inverseZ = 1.0 / q.z;
    float x = q.x * inverseZ;
    float y = q.y * inverseZ;
    float r2 = x * x + y * y;
    float radial = 1.0 + r2 * (colourLens[0] + r2 * (colourLens[1] + r2 * colourLens[4]));
    float xd = x * radial + 2.0 * colourLens[2] * x * y + colourLens[3] * (r2 + 2.0 * x * x);
    float yd = y * radial + colourLens[2] * (r2 + 2.0 * y * y) + 2.0 * colourLens[3] * x * y;
    vec2 pixel = colourIntrinsics.xy * vec2(xd, yd) + colourIntrinsics.zw;
    vec2 low = vec2(-0.5 - colourMarginPixels);
    vec2 high = vec2(cameraSize) - 0.5 + colourMarginPixels;
    bool lands = q.z > 0.0 && r2 <= colourMaxRadius2 && all(greaterThanEqual(pixel, low)) &&
                 all(lessThan(pixel, high));
    return lands ? vec3(pixel, q.z) : vec3(0.0);
}

vec4 seenCameraColor(ivec2 pixel, ivec2 mapSize, vec3 point) {
    const vec4 unseen = vec4(vec3(kUnseenGray), 0.0);
    if (cameraFormat == 0)
        return vec4(vec3(kUnseenGray), 1.0);
    if (!registered) // processing::cameraPixelOf, in integers
        return vec4(cameraRgb((2 * pixel + 1) * cameraSize / (2 * mapSize)), 1.0);
    vec3 c = toColourImage(point);
    if (!(c.z > 0.0) || any(lessThan(c.xy, vec2(-0.5))) || any(greaterThanEqual(c.xy, vec2(cameraSize) - 0.5)))
        return unseen;
    ivec2 at = min(ivec2(c.xy + 0.5), cameraSize - 1);
    float nearest = texelFetch(colourNearest, at + nearestMargin, 0).r * kNearestFarMeters;
    // processing::sameSurfaceMeters
    if (c.z > nearest + 0.01 + 0.02 * c.z)
        return unseen;
    return vec4(cameraRgb(at), 1.0);
}

vec3 cameraPointColor(ivec2 pixel, ivec2 mapSize, vec3 point) {
    vec4 colour = seenCameraColor(pixel, mapSize, point);
    return colour.a > 0.0 ? colour.rgb : vec3(kUnseenGray);
}
)glsl";

Status CameraColours::init() {
    const std::string vertexShader =
        std::string("#version 330 core\n") + kFrameTexturesGlsl + kCameraColoursGlsl + kNearestVertexMain;
    Expected<gl::Program> program = gl::Program::link(vertexShader, kDepthOnlyFragmentShader);
    if (!program)
        return Error{"camera colour visibility shaders: " + program.error().message};
    nearestProgram_ = std::move(program).value();
    FrameTextures::connectSamplers(nearestProgram_);
    connectSamplers(nearestProgram_);
    glUseProgram(0);
    Expected<gl::Program> image =
        gl::Program::link(gl::kFullscreenVertexShader,
                          std::string("#version 330 core\n") + kCameraColoursGlsl + kImageFragmentMain);
    if (!image)
        return Error{"camera image shaders: " + image.error().message};
    imageProgram_ = std::move(image).value();
    connectSamplers(imageProgram_);
    glUseProgram(0);
    Expected<gl::Program> seen = gl::Program::link(gl::kFullscreenVertexShader,
                                                   std::string("#version 330 core\n") + kFrameTexturesGlsl +
                                                       kCameraColoursGlsl + kSeenColoursFragmentMain);
    if (!seen)
        return Error{"colour overlay shaders: " + seen.error().message};
    seenProgram_ = std::move(seen).value();
    FrameTextures::connectSamplers(seenProgram_);
    connectSamplers(seenProgram_);
    if (Status s = linkAlignedPrograms(vertexShader); !s)
        return s;
    glUseProgram(0);
    nearestFramebuffer_ = gl::Framebuffer::create();
    emptyVertexArray_ = gl::VertexArray::create();
    return Status::success();
}

// One program per colormap, as PanelRenderer has (colormapGlsl says why).
Status CameraColours::linkAlignedPrograms(const std::string& vertexShader) {
    for (int c = 0; c < kColormapCount; ++c) {
        Expected<gl::Program> aligned = gl::Program::link(
            vertexShader, std::string("#version 330 core\n") + colormapGlsl(static_cast<Colormap>(c)) +
                              kAlignedFragmentMain);
        if (!aligned)
            return Error{"aligned depth shaders: " + aligned.error().message};
        gl::Program& program = alignedPrograms_[static_cast<std::size_t>(c)];
        program = std::move(aligned).value();
        FrameTextures::connectSamplers(program);
        connectSamplers(program);
    }
    return Status::success();
}

void CameraColours::connectSamplers(const gl::Program& program) {
    glUseProgram(program.id());
    glUniform1i(program.uniformLocation("cameraLuma"), kLumaUnit);
    glUniform1i(program.uniformLocation("cameraChroma"), kChromaUnit);
    glUniform1i(program.uniformLocation("colourNearest"), kNearestUnit);
}

void CameraColours::uploadPlane(Plane& plane, GLint internalFormat, GLenum format, int width, int height,
                                const void* pixels) {
    gl::bindNearestTexture(plane.texture);
    // A new internal format (a camera switching from NV12 to RGB) needs new storage as a new size does.
    GLint current = 0;
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &current);
    if (width == plane.width && height == plane.height && current == internalFormat) {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format, GL_UNSIGNED_BYTE, pixels);
        return;
    }
    glTexImage2D(GL_TEXTURE_2D, 0, internalFormat, width, height, 0, format, GL_UNSIGNED_BYTE, pixels);
    plane.width = width;
    plane.height = height;
}

void CameraColours::uploadImage(const frame::CapturedImage& image) {
    if (image.bytes == uploadedBytes_ && image.bytes)
        return;
    uploadedBytes_ = image.bytes;
    format_ = kFormatNone;
    if (!usableImage(image))
        return;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const int w = image.width, h = image.height, pairs = (w + 1) / 2;
    const std::uint8_t* bytes = image.bytes->data();
    switch (image.format) {
    case frame::PixelFormat::Nv12:
        uploadPlane(luma_, GL_R8, GL_RED, w, h, bytes);
        uploadPlane(chroma_, GL_RG8, GL_RG, pairs, (h + 1) / 2, bytes + static_cast<std::size_t>(w) * h);
        format_ = kFormatNv12;
        break;
    case frame::PixelFormat::Yuyv:
        uploadPlane(luma_, GL_RGBA8, GL_RGBA, pairs, h, bytes);
        format_ = kFormatYuyv;
        break;
    case frame::PixelFormat::Rgb24:
        uploadPlane(luma_, GL_RGB8, GL_RGB, w, h, bytes);
        format_ = kFormatRgb;
        break;
    case frame::PixelFormat::Jpeg: // decoded by the engine before it reaches here
        return;
    }
    width_ = w;
    height_ = h;
    ++uploads_;
}

void CameraColours::setRig(std::shared_ptr<const frame::RigCalibration> rig) {
    if (rig && processing::isSingleCamera(*rig))
        rig.reset();
    if (rig != rig_)
        projection_.reset();
    rig_ = std::move(rig);
}

const processing::ColourProjection&
CameraColours::projection(const frame::Intrinsics& depthIntrinsics) const {
    if (!projection_ || !(projection_->first == depthIntrinsics) ||
        projection_->second.colourCamera.intrinsics.width != width_ ||
        projection_->second.colourCamera.intrinsics.height != height_)
        projection_.emplace(depthIntrinsics,
                            processing::colourProjection(*rig_, depthIntrinsics, width_, height_));
    return projection_->second;
}

int CameraColours::marginPixels(const frame::Intrinsics& depthIntrinsics) const {
    return static_cast<int>(std::ceil(projection(depthIntrinsics).marginPixels));
}

void CameraColours::renderNearest(const FrameTextures& textures) {
    if (!rig_ || format_ == kFormatNone || !textures.hasDepth() || !textures.depthIntrinsics().valid())
        return;
    const int margin = marginPixels(textures.depthIntrinsics());
    const int width = width_ + 2 * margin, height = height_ + 2 * margin;
    if (nearest_.width != width || nearest_.height != height) {
        gl::bindNearestTexture(nearest_.texture);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, width, height, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                     nullptr);
        nearest_.width = width;
        nearest_.height = height;
        glBindFramebuffer(GL_FRAMEBUFFER, nearestFramebuffer_.id());
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, nearest_.texture.id(), 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, nearestFramebuffer_.id());
    glViewport(0, 0, width, height);
    nearestPointWinsState();
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(nearestProgram_.id());
    setDepthIntrinsics(nearestProgram_, textures);
    setUniforms(nearestProgram_, textures);
    textures.bind();
    bind();
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArrays(GL_POINTS, 0, textures.depthWidth() * textures.depthHeight());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    ++nearestPasses_;
}

void CameraColours::renderImage(RenderTarget& target, int width, int height) {
    if (format_ == kFormatNone || width <= 0 || height <= 0 || !target.resize(width, height))
        return;
    target.bind();
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(imageProgram_.id());
    glUniform1i(imageProgram_.uniformLocation("cameraFormat"), format_);
    glUniform2i(imageProgram_.uniformLocation("cameraSize"), width_, height_);
    glUniform2i(imageProgram_.uniformLocation("outputSize"), width, height);
    bind();
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    ++imagePasses_;
}

void CameraColours::renderSeenColours(RenderTarget& target, const FrameTextures& whole, int step) {
    step = std::max(step, 1);
    if (!whole.hasDepth() ||
        !target.resize((whole.depthWidth() + step - 1) / step, (whole.depthHeight() + step - 1) / step))
        return;
    // Without an image the colour camera sees nothing: the overlay is left empty.
    if (format_ != kFormatNone && registers())
        renderNearest(whole);
    target.bindAndClear(0.0f, 0.0f, 0.0f, 0.0f);
    if (format_ == kFormatNone) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        return;
    }
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(seenProgram_.id());
    setDepthIntrinsics(seenProgram_, whole);
    glUniform1i(seenProgram_.uniformLocation("sampleStep"), step);
    glUniform2i(seenProgram_.uniformLocation("outputSize"), target.width(), target.height());
    setUniforms(seenProgram_, whole);
    whole.bind();
    bind();
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    ++seenPasses_;
}

void CameraColours::renderAlignedDepth(RenderTarget& target, const FrameTextures& textures, int width,
                                       int height, const AlignedColours& colours) {
    if (!rig_ || width <= 0 || height <= 0 || !textures.hasDepth() || !textures.depthIntrinsics().valid() ||
        !target.resize(width, height))
        return;
    target.bindAndClear(0.0f, 0.0f, 0.0f, 0.0f);
    const processing::ColourProjection p =
        processing::colourProjection(*rig_, textures.depthIntrinsics(), width, height);
    // GL drops a point whose centre is outside the viewport: the viewport reaches the margin past the
    // target on every side, so that samples just outside still cover its border pixels (the pixels out
    // there are not the framebuffer's and are not drawn).
    const int margin = static_cast<int>(std::ceil(p.marginPixels));
    glViewport(-margin, -margin, width + 2 * margin, height + 2 * margin);
    nearestPointWinsState();
    glEnable(GL_PROGRAM_POINT_SIZE);
    const gl::Program& program = alignedPrograms_[static_cast<std::size_t>(colours.colormap)];
    glUseProgram(program.id());
    setDepthIntrinsics(program, textures);
    glUniform2i(program.uniformLocation("cameraSize"), width, height);
    glUniform1i(program.uniformLocation("topDown"), 1);
    glUniform1i(program.uniformLocation("outputHeight"), height);
    setProjection(program, p);
    glUniform1f(program.uniformLocation("minMeters"), colours.minMeters);
    glUniform1f(program.uniformLocation("inverseRangeMeters"),
                1.0f / std::max(colours.maxMeters - colours.minMeters, kMinRangeMeters));
    textures.bind();
    glBindVertexArray(emptyVertexArray_.id());
    glDrawArrays(GL_POINTS, 0, textures.depthWidth() * textures.depthHeight());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    ++alignedPasses_;
}

void CameraColours::bind() const {
    gl::bindTextureUnits({{kLumaUnit, luma_.texture.id()},
                          {kChromaUnit, chroma_.texture.id()},
                          {kNearestUnit, nearest_.texture.id()}});
}

void CameraColours::setUniforms(const gl::Program& program, const FrameTextures& textures) const {
    glUniform1i(program.uniformLocation("cameraFormat"), format_);
    glUniform2i(program.uniformLocation("cameraSize"), std::max(width_, 1), std::max(height_, 1));
    const bool registered = rig_ && format_ != kFormatNone && textures.depthIntrinsics().valid();
    glUniform1i(program.uniformLocation("registered"), registered ? 1 : 0);
    if (registered)
        setProjection(program, projection(textures.depthIntrinsics()));
}

void CameraColours::setProjection(const gl::Program& program, const processing::ColourProjection& p) {
    GLfloat rotation[9];
    std::transform(p.depthToColour.rotation.begin(), p.depthToColour.rotation.end(), rotation,
                   [](double v) { return static_cast<GLfloat>(v); });
    glUniformMatrix3fv(program.uniformLocation("depthToColourRotation"), 1, GL_TRUE, rotation); // row-major
    const auto& t = p.depthToColour.translationMeters;
    glUniform3f(program.uniformLocation("depthToColourTranslation"), static_cast<float>(t[0]),
                static_cast<float>(t[1]), static_cast<float>(t[2]));
    const frame::Intrinsics& c = p.colourCamera.intrinsics;
    glUniform4f(program.uniformLocation("colourIntrinsics"), static_cast<float>(c.fx),
                static_cast<float>(c.fy), static_cast<float>(c.cx), static_cast<float>(c.cy));
    GLfloat lens[5];
    std::transform(p.colourCamera.lens.coefficients.begin(), p.colourCamera.lens.coefficients.end(), lens,
                   [&](double v) {
                       return p.colourCamera.lens.model == frame::LensModel::None ? 0.0f
                                                                                  : static_cast<GLfloat>(v);
                   });
    glUniform1fv(program.uniformLocation("colourLens"), 5, lens);
    glUniform1f(program.uniformLocation("colourMaxRadius2"), finiteOrMax(p.maxRadius2));
    glUniform1f(program.uniformLocation("colourMarginPixels"), static_cast<float>(p.marginPixels));
    glUniform1f(program.uniformLocation("halfPerDepthOverColourZ"),
                static_cast<float>(p.halfPerDepthOverColourZ));
    glUniform1i(program.uniformLocation("nearestMargin"), static_cast<int>(std::ceil(p.marginPixels)));
}

} // namespace dc::render
