#pragma once

#include "processing/shown_frame.h"
#include "tool/gpu_clock.h"

#include <optional>
#include <string>

namespace dc::tool {

// A drawn frame's medians: wall time to glFinish, the GL thread's CPU time submitting it (up to the
// glFinish, which a driver may spend spinning), and the GPU's own time for it (a GL_TIME_ELAPSED query).
// On a GPU the two overlap from frame to frame; the wall time adds them.
struct GlFrameMs {
    double wall = 0.0;
    double cpu = 0.0;
    double gpu = 0.0;
    double gpuClockMhz = 0.0; // the GPU's graphics clock over the frames, median (0: not known)
};

// The peer every viewer bench is measured against: GL_POINTS of every shown sample through the cloud
// shader into a target of the cloud panel's size, the view turning each frame, nothing else drawn; the
// medians over `frames` (after a warm-up), each ended by glFinish. Back to back, or one every 1/paceFps
// seconds as the viewer's frames come at a camera's rate: a GPU that idles between frames lowers its clock,
// and only a peer drawn at the same pace shares it. Needs a current context.
GlFrameMs bareGlPoints(const processing::ShownFrame& shown, int width, int height, int frames,
                       double paceFps = 0.0);
// The clock of the GPU the current context draws on, opened once (none where GpuClock::open finds none).
const std::optional<GpuClock>& currentGpuClock();
// A text for the clock, " at a GPU clock of N of M MHz", or empty when it is not known.
std::string gpuClockText(double mhz);

} // namespace dc::tool
