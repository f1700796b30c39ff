#include "render/gl_context.h"

#include <epoxy/gl.h>

#include <cstdio>
#include <utility>

namespace dc::render {

namespace {

constexpr int kMinGlVersion = 33; // epoxy's encoding of 3.3: no compute shaders, no GL 4.x

Error noContext(const std::string& reason) {
    char code[32];
    std::snprintf(code, sizeof code, " (EGL error 0x%04x)", static_cast<unsigned>(eglGetError()));
    return Error{"no OpenGL 3.3 context available: " + reason + code};
}

// The surfaceless platform needs neither X nor a GPU; the default display is the fallback for EGL
// implementations without it. The EXT entry point, not EGL 1.5's eglGetPlatformDisplay: before a display
// exists libepoxy cannot tell the EGL version and refuses to resolve core 1.5 functions.
EGLDisplay openDisplay(bool& surfaceless) {
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base") &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) {
            surfaceless = true;
            return display;
        }
    }
    surfaceless = false;
    EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr))
        return display;
    return EGL_NO_DISPLAY;
}

bool chooseConfig(EGLDisplay display, bool surfaceless, EGLConfig& config) {
    // Without a surface the config only has to support desktop GL; the fallback renders into a pbuffer.
    const EGLint surfaceType = surfaceless ? 0 : EGL_PBUFFER_BIT;
    // One attribute-value pair per line.
    // clang-format off
    const EGLint attributes[] = {EGL_SURFACE_TYPE, surfaceType,
                                 EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                 EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                                 EGL_NONE};
    // clang-format on
    EGLint count = 0;
    return eglChooseConfig(display, attributes, &config, 1, &count) && count == 1;
}

EGLContext createCoreContext(EGLDisplay display, EGLConfig config) {
    // One attribute-value pair per line.
    // clang-format off
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3,
                                 EGL_CONTEXT_MINOR_VERSION, 3,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    // clang-format on
    return eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
}

} // namespace

Expected<EglContext> EglContext::createHeadless() {
    EglContext result; // cleans up whatever was created if a later step fails
    bool surfaceless = false;
    result.display_ = openDisplay(surfaceless);
    if (result.display_ == EGL_NO_DISPLAY)
        return noContext("no EGL display (is Mesa's libEGL installed?)");
    if (!eglBindAPI(EGL_OPENGL_API))
        return noContext("EGL cannot bind desktop OpenGL");
    EGLConfig config = nullptr;
    if (!chooseConfig(result.display_, surfaceless, config))
        return noContext("no EGL config for desktop OpenGL");
    result.context_ = createCoreContext(result.display_, config);
    if (result.context_ == EGL_NO_CONTEXT)
        return noContext("the driver refused a 3.3 core profile context");
    if (!surfaceless) {
        const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        result.surface_ = eglCreatePbufferSurface(result.display_, config, size);
        if (result.surface_ == EGL_NO_SURFACE)
            return noContext("cannot create a pbuffer surface");
    }
    if (Status current = result.makeCurrent(); !current)
        return current.error();
    if (!epoxy_is_desktop_gl() || epoxy_gl_version() < kMinGlVersion)
        return Error{"no OpenGL 3.3 context available: the context reports version " +
                     std::to_string(epoxy_gl_version())};
    return result;
}

EglContext::EglContext(EglContext&& other) noexcept
    : display_(std::exchange(other.display_, EGL_NO_DISPLAY)),
      surface_(std::exchange(other.surface_, EGL_NO_SURFACE)),
      context_(std::exchange(other.context_, EGL_NO_CONTEXT)) {}

EglContext& EglContext::operator=(EglContext&& other) noexcept {
    if (this != &other) {
        destroy();
        display_ = std::exchange(other.display_, EGL_NO_DISPLAY);
        surface_ = std::exchange(other.surface_, EGL_NO_SURFACE);
        context_ = std::exchange(other.context_, EGL_NO_CONTEXT);
    }
    return *this;
}

EglContext::~EglContext() {
    destroy();
}

void EglContext::destroy() {
    if (display_ == EGL_NO_DISPLAY)
        return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT)
        eglDestroyContext(display_, context_);
    if (surface_ != EGL_NO_SURFACE)
        eglDestroySurface(display_, surface_);
    eglTerminate(display_);
    display_ = EGL_NO_DISPLAY;
    surface_ = EGL_NO_SURFACE;
    context_ = EGL_NO_CONTEXT;
}

Status EglContext::makeCurrent() const {
    // With the surfaceless platform EGL_NO_SURFACE is the draw surface (EGL_KHR_surfaceless_context).
    if (!eglMakeCurrent(display_, surface_, surface_, context_))
        return noContext("eglMakeCurrent failed");
    return Status::success();
}

std::string EglContext::rendererName() const {
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return name ? name : "";
}

} // namespace dc::render
