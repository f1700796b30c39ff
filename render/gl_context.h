#pragma once

#include "base/expected.h"

#include <epoxy/egl.h>

#include <string>

namespace dc::render {

// An OpenGL 3.3 core context without a window, for tests and headless rendering: all drawing goes to
// RenderTargets. Prefers Mesa's surfaceless platform (no X display, no GPU needed: llvmpipe renders) and
// falls back to the default display with a 1x1 pbuffer.
//
// The destructor terminates the EGL display, which ends every context on it, so keep one EglContext per
// process and destroy it after every GL object.
class EglContext {
public:
    static Expected<EglContext> createHeadless();

    EglContext(EglContext&& other) noexcept;
    EglContext& operator=(EglContext&& other) noexcept;
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    ~EglContext();

    Status makeCurrent() const;
    // GL_RENDERER of the current context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string rendererName() const;

private:
    EglContext() = default;
    void destroy();

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLSurface surface_ = EGL_NO_SURFACE;
    EGLContext context_ = EGL_NO_CONTEXT;
};

} // namespace dc::render
