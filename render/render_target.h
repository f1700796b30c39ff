#pragma once

#include "base/expected.h"
#include "render/gl_objects.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dc::render {

// How the color texture is filtered when the UI scales it: Linear suits the cloud, Nearest keeps the
// pixels of a data panel visible when zoomed in.
enum class Sampling { Linear, Nearest };

// A rectangle of framebuffer pixels, GL's way: (x, y) is its bottom-left corner.
struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0;
};

// Clears the colour of `rect` of the bound draw framebuffer alone (a picture redrawn only where it changed).
void clearColorWithin(PixelRect rect, float r, float g, float b);

// Whether a target has a depth buffer: the cloud's depth test needs one; a 2D panel or the UI's own
// composite does not, and each frame's clear would write it for nothing.
enum class DepthBuffer { With, Without };

// The RGBA8 pixels of `framebuffer` (0: the window's back buffer), width x height from the origin, top
// row first as images and PNG files have them; empty for an empty size.
std::vector<std::uint8_t> readFramebufferRgba(GLuint framebuffer, int width, int height);

// An offscreen framebuffer: an RGBA8 color texture (what the UI shows) and, unless left out, a depth
// renderbuffer. Holds no GL object until the first resize(), so it can be built before a context.
//
// GL stores the color texture bottom row first: show it with ImGui::Image(id, size, {0, 1}, {1, 0}).
// readRgba() and savePng() already return the image top row first.
class RenderTarget {
public:
    explicit RenderTarget(Sampling sampling = Sampling::Linear, DepthBuffer depth = DepthBuffer::With)
        : sampling_(sampling), hasDepth_(depth == DepthBuffer::With) {}

    // Reallocates the attachments for a new size; a no-op when the size is unchanged.
    Status resize(int width, int height);
    // Binds the framebuffer for drawing and sets the viewport to cover it.
    void bind() const;
    // Binds it and clears colour and the depth buffer if it has one (colour components in [0, 1]).
    void bindAndClear(float r, float g, float b, float a = 1.0f) const;
    // Binds it and clears the colour of `rect` alone (clearColorWithin).
    void bindAndClearWithin(PixelRect rect, float r, float g, float b) const;
    void setSampling(Sampling sampling);

    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return width_ == 0 || height_ == 0; }
    GLuint colorTexture() const { return color_.id(); }

    // Copies the colour image into `destination` of the bound draw framebuffer, scaled when the sizes
    // differ, only within `clip`: no shader, no blending, no texture sampling. The cheapest way a finished
    // image reaches the window (on llvmpipe a copy of rows when the formats match); the draw framebuffer
    // must not be multisampled.
    void blitInto(PixelRect destination, PixelRect clip) const;

    // Tightly packed RGBA rows, top row first; empty before the first resize().
    std::vector<std::uint8_t> readRgba() const;
    Status savePng(const std::string& path) const;

private:
    void applySampling() const;

    gl::Framebuffer framebuffer_;
    gl::Texture color_;
    gl::Renderbuffer depth_;
    Sampling sampling_;
    bool hasDepth_ = true;
    int width_ = 0;
    int height_ = 0;
};

} // namespace dc::render
