#pragma once

#include "processing/shown_frame.h"

namespace dc::tool {

// The peer every viewer bench is measured against: GL_POINTS of every shown sample through the cloud
// shader into a target of the cloud panel's size, the view turning each frame, nothing else drawn; the
// median milliseconds over `frames` (after a warm-up), each ended by glFinish. Needs a current context.
double bareGlPointsMs(const processing::ShownFrame& shown, int width, int height, int frames);

} // namespace dc::tool
