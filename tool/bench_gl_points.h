#pragma once

#include "processing/shown_frame.h"

namespace dc::tool {

// A drawn frame's medians: wall time to glFinish, the GL thread's CPU time submitting it (up to the
// glFinish, which a driver may spend spinning), and the GPU's own time for it (a GL_TIME_ELAPSED query).
// On a GPU the two overlap from frame to frame; the wall time adds them.
struct GlFrameMs {
    double wall = 0.0;
    double cpu = 0.0;
    double gpu = 0.0;
};

// The peer every viewer bench is measured against: GL_POINTS of every shown sample through the cloud
// shader into a target of the cloud panel's size, the view turning each frame, nothing else drawn; the
// medians over `frames` (after a warm-up), each ended by glFinish. Needs a current context.
GlFrameMs bareGlPoints(const processing::ShownFrame& shown, int width, int height, int frames);

} // namespace dc::tool
