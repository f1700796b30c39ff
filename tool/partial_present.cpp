#include "tool/partial_present.h"

#include <epoxy/glx.h>

namespace dc::tool {

std::optional<PartialPresenter> PartialPresenter::forCurrentContext() {
    Display* display = glXGetCurrentDisplay();
    const GLXDrawable drawable = glXGetCurrentDrawable();
    if (!display || !drawable ||
        !epoxy_has_glx_extension(display, DefaultScreen(display), "GLX_MESA_copy_sub_buffer"))
        return std::nullopt;
    return PartialPresenter(display, drawable);
}

void PartialPresenter::copy(render::PixelRect rect) const {
    glXCopySubBufferMESA(static_cast<Display*>(display_), drawable_, rect.x, rect.y, rect.width, rect.height);
}

} // namespace dc::tool
