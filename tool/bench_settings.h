#pragma once

#include "ui/settings.h"

namespace dc::tool {

// Every stage on: the cloud in camera colours, all panels, fog and aura, smoothing and upsampling (what the
// engine and soak benches load the viewer with).
inline ui::Settings everyStageSettings() {
    ui::Settings s;
    s.panels.fog = true;
    s.panels.aura = true;
    s.processing.smoothing = true;
    s.processing.upsampling = true;
    return s;
}

} // namespace dc::tool
