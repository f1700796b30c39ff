#include "tool/partial_present.h"

#include <epoxy/glx.h>

namespace dc::tool {
namespace {

// The errors the X server sent while an ErrorTrap was alive. Xlib calls its handler on the thread that
// waits for the reply, which is the GL thread, the only one that presents.
int trappedErrors = 0;

int countError(Display*, XErrorEvent*) {
    ++trappedErrors;
    return 0;
}

// Catches the X errors of the requests made in its lifetime instead of Xlib's default handler, which exits.
// The handler is set around each request rather than once: GLFW puts the default back after its own traps.
class ErrorTrap {
public:
    explicit ErrorTrap(Display* display) : display_(display), previous_(XSetErrorHandler(countError)) {
        trappedErrors = 0;
    }
    ErrorTrap(const ErrorTrap&) = delete;
    ErrorTrap& operator=(const ErrorTrap&) = delete;
    ~ErrorTrap() { XSetErrorHandler(previous_); }

    // Waits for the server to have handled every request so far, so their errors have come in.
    bool clean() {
        XSync(display_, False);
        return trappedErrors == 0;
    }

private:
    Display* display_;
    XErrorHandler previous_;
};

} // namespace

std::optional<PartialPresenter> PartialPresenter::forCurrentContext() {
    Display* display = glXGetCurrentDisplay();
    const GLXDrawable drawable = glXGetCurrentDrawable();
    if (!display || !drawable ||
        !epoxy_has_glx_extension(display, DefaultScreen(display), "GLX_MESA_copy_sub_buffer"))
        return std::nullopt;
    return PartialPresenter(display, drawable);
}

bool PartialPresenter::copy(render::PixelRect rect) const {
    Display* display = static_cast<Display*>(display_);
    ErrorTrap trap(display);
    glXCopySubBufferMESA(display, drawable_, rect.x, rect.y, rect.width, rect.height);
    return trap.clean();
}

bool PartialPresenter::resizeBackBuffer() const {
    Display* display = static_cast<Display*>(display_);
    ErrorTrap trap(display);
    glXSwapBuffers(display, drawable_);
    return trap.clean();
}

} // namespace dc::tool
