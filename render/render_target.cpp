#include "render/render_target.h"

#include "frame/image_io.h"

#include <algorithm>

namespace dc::render {

Status RenderTarget::resize(int width, int height) {
    if (width == width_ && height == height_)
        return Status::success();
    if (width <= 0 || height <= 0)
        return Error{"render target size must be positive, not " + std::to_string(width) + "x" +
                     std::to_string(height)};
    if (!framebuffer_) {
        framebuffer_ = gl::Framebuffer::create();
        color_ = gl::Texture::create();
        if (hasDepth_)
            depth_ = gl::Renderbuffer::create();
    }
    glBindTexture(GL_TEXTURE_2D, color_.id());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    applySampling();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_.id(), 0);
    if (depth_) {
        glBindRenderbuffer(GL_RENDERBUFFER, depth_.id());
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
    }
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        width_ = height_ = 0;
        return Error{"render target framebuffer is incomplete (status " + std::to_string(status) + ")"};
    }
    width_ = width;
    height_ = height;
    return Status::success();
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glViewport(0, 0, width_, height_);
}

void RenderTarget::bindAndClear(float r, float g, float b, float a) const {
    bind();
    glClearColor(r, g, b, a);
    glClearDepth(1.0);
    glClear(depth_ ? GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT : GL_COLOR_BUFFER_BIT);
}

void clearColorWithin(PixelRect rect, float r, float g, float b) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(rect.x, rect.y, rect.width, rect.height);
    glClearColor(r, g, b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
}

void RenderTarget::bindAndClearWithin(PixelRect rect, float r, float g, float b) const {
    bind();
    clearColorWithin(rect, r, g, b);
}

void RenderTarget::setSampling(Sampling sampling) {
    sampling_ = sampling;
    if (color_) {
        glBindTexture(GL_TEXTURE_2D, color_.id());
        applySampling();
    }
}

// Expects the color texture to be bound to GL_TEXTURE_2D.
void RenderTarget::applySampling() const {
    const GLint filter = sampling_ == Sampling::Nearest ? GL_NEAREST : GL_LINEAR;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
}

void RenderTarget::blitInto(PixelRect destination, PixelRect clip) const {
    if (empty() || destination.width <= 0 || destination.height <= 0 || clip.width <= 0 || clip.height <= 0)
        return;
    GLint previousRead = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previousRead);
    const GLboolean scissored = glIsEnabled(GL_SCISSOR_TEST);
    glEnable(GL_SCISSOR_TEST);
    glScissor(clip.x, clip.y, clip.width, clip.height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.id());
    const bool sameSize = destination.width == width_ && destination.height == height_;
    glBlitFramebuffer(0, 0, width_, height_, destination.x, destination.y, destination.x + destination.width,
                      destination.y + destination.height, GL_COLOR_BUFFER_BIT,
                      sameSize ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previousRead));
    if (!scissored)
        glDisable(GL_SCISSOR_TEST);
}

std::vector<std::uint8_t> readFramebufferRgba(GLuint framebuffer, int width, int height) {
    if (width <= 0 || height <= 0)
        return {};
    const auto rowBytes = static_cast<std::size_t>(width) * 4;
    std::vector<std::uint8_t> bottomUp(rowBytes * height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1); // rows of any width are packed without padding
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);

    // GL's window origin is the bottom-left corner; images and PNG files start with the top row.
    std::vector<std::uint8_t> topDown(bottomUp.size());
    for (int row = 0; row < height; ++row) {
        const auto source = bottomUp.begin() + static_cast<std::ptrdiff_t>(rowBytes * (height - 1 - row));
        std::copy_n(source, rowBytes, topDown.begin() + static_cast<std::ptrdiff_t>(rowBytes * row));
    }
    return topDown;
}

std::vector<std::uint8_t> RenderTarget::readRgba() const {
    return empty() ? std::vector<std::uint8_t>{} : readFramebufferRgba(framebuffer_.id(), width_, height_);
}

Status RenderTarget::savePng(const std::string& path) const {
    if (empty())
        return Error{"cannot save " + path + ": nothing has been rendered"};
    const std::vector<std::uint8_t> rgba = readRgba();
    return frame::writeRgbaPng(path, width_, height_, rgba.data());
}

} // namespace dc::render
