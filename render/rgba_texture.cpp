#include "render/rgba_texture.h"

namespace dc::render {

void RgbaTexture::upload(int width, int height, const std::uint8_t* rgba) {
    upload(width, height, GL_RGBA, rgba);
}

void RgbaTexture::uploadRgb(int width, int height, const std::uint8_t* rgb) {
    upload(width, height, GL_RGB, rgb);
}

void RgbaTexture::upload(int width, int height, GLenum format, const std::uint8_t* pixels) {
    if (width <= 0 || height <= 0 || pixels == nullptr)
        return;
    if (!texture_)
        texture_ = gl::Texture::create();
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (width != width_ || height != height_) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, format, GL_UNSIGNED_BYTE, pixels);
        const GLint filter = sampling_ == Sampling::Nearest ? GL_NEAREST : GL_LINEAR;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        width_ = width;
        height_ = height;
    } else {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format, GL_UNSIGNED_BYTE, pixels);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
}

} // namespace dc::render
