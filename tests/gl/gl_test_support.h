#pragma once

#include "frame/color.h"
#include "frame/frame.h"
#include "render/frame_textures.h"
#include "render/gl_context.h"

#include <epoxy/gl.h>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <vector>

namespace dc::render::test {

// A clear colour that no surface of the synthetic scene has, so a background pixel is never mistaken for
// a drawn one.
inline const glm::vec3 kMagentaBackground{1.0f, 0.0f, 1.0f};

// Gives every test a real context (Mesa llvmpipe through EGL). Missing GL fails the test rather than
// skipping it: the gl tier must not pass silently on a machine that cannot run it. The context is made
// before and destroyed after everything the test body owns, so no GL object outlives it.
class GlTest : public ::testing::Test {
protected:
    void SetUp() override;

private:
    std::optional<EglContext> context_;
};

// Drains GL's error queue; fails listing every error found.
::testing::AssertionResult noGlError();

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 0;
    bool operator==(const Rgba&) const = default;
};
std::ostream& operator<<(std::ostream& out, const Rgba& c);

Rgba pixelAt(const std::vector<std::uint8_t>& rgba, int width, int x, int y);
// An opaque 8-bit color, clamped and rounded the way the GPU stores a float color in an RGBA8 target.
Rgba toRgba(frame::Rgb c);
Rgba toRgba(const std::array<float, 3>& c);
// Every channel within `tolerance` steps of 255.
::testing::AssertionResult near(Rgba actual, Rgba expected, int tolerance);

using ColorFunction = std::function<frame::Rgb(int x, int y)>;
// Distinct colours, constant over `blockPixels`-wide squares aligned to multiples of the block size, so
// that 2x2 chroma subsampling and bilinear sampling at block interiors reproduce them exactly.
ColorFunction blockColors(int blockPixels);

frame::CapturedImage nv12Image(int width, int height, const ColorFunction& color);
frame::CapturedImage yuyvImage(int width, int height, const ColorFunction& color);
frame::CapturedImage rgb24Image(int width, int height, const ColorFunction& color);

// A frame with the given depth (and confidence), and a camera image whose intrinsics scale to
// `depthIntrinsics` at the depth map's resolution, as ARKit's do.
frame::Frame makeFrame(frame::DepthData depth, frame::CapturedImage image,
                       const frame::Intrinsics& cameraIntrinsics);

// Uploads the frame as the engine shows a raw frame: sceneDepth with Frame::depthIntrinsics(), and the
// colour of each point (processing::pointColours of the camera image).
void uploadFrame(FrameTextures& textures, const frame::Frame& frame);

// A pinhole projection through `k` into a `width` x `height` target: the centre of depth pixel (u, v)
// lands on the centre of target pixel (u, v) counted from the top-left, as RenderTarget::readRgba()
// returns them. Depth maps to clip space between 0.1 m and 100 m.
glm::mat4 pinholeViewProjection(const frame::Intrinsics& k, int width, int height);

} // namespace dc::render::test
