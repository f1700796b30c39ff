#pragma once

#include "render/colormap.h"

namespace dc::ui {

// How the depth panel maps meters to colour: the range actually used (fixed or automatic) and the ramp.
struct DepthLegend {
    float minMeters = 0.0f;
    float maxMeters = 2.5f;
    render::Colormap colormap = render::Colormap::Jet;
    bool automatic = false;
};

} // namespace dc::ui
