#pragma once

#include "render/gl_objects.h"
#include "render/render_target.h"

#include <cstdint>

namespace dc::render {

// An 8-bit RGBA or RGB image made on the CPU (fog, aura, the camera panel) as a texture for ImGui::Image:
// row 0 is the top, so the default texture coordinates show it upright. Reallocated only when the size
// changes.
class RgbaTexture {
public:
    explicit RgbaTexture(Sampling sampling = Sampling::Linear) : sampling_(sampling) {}
    void upload(int width, int height, const std::uint8_t* rgba);
    void uploadRgb(int width, int height, const std::uint8_t* rgb);
    GLuint id() const { return texture_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    void upload(int width, int height, GLenum format, const std::uint8_t* pixels);

    gl::Texture texture_;
    Sampling sampling_;
    int width_ = 0;
    int height_ = 0;
};

} // namespace dc::render
