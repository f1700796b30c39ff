#pragma once

#include "render/render_target.h"

#include <optional>

namespace dc::tool {

// Shows parts of a window's back buffer without a swap, through GLX_MESA_copy_sub_buffer. With no swap the
// back buffer keeps what was drawn into it, so a frame need only draw what changed, and only that is copied
// to the window. No Xlib header here: Xlib's macros (Status, None, Bool) would clash with the project's.
//
// A window resized by someone else (a window manager, xdotool) between the last swap and a copy leaves the
// back buffer at its old size, and the X server refuses the copy (BadValue from ShmPutImage). Xlib's default
// handler would end the process on that error; here it is caught, and the caller draws the next frame whole.
class PartialPresenter {
public:
    // The presenter of the current GLX context's drawable; none where GLX or the extension is missing.
    static std::optional<PartialPresenter> forCurrentContext();
    // Copies the rectangle of the back buffer to the window. Flushes GL first, as a swap does. False where
    // the X server refused it.
    [[nodiscard]] bool copy(render::PixelRect rect) const;
    // Swaps once, which gives the back buffer the window's current size. False where the X server refused it.
    [[nodiscard]] bool resizeBackBuffer() const;

private:
    PartialPresenter(void* display, unsigned long drawable) : display_(display), drawable_(drawable) {}

    void* display_;
    unsigned long drawable_;
};

} // namespace dc::tool
