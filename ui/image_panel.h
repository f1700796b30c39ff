#pragma once

#include "ui/panels.h"

namespace dc::ui {

// The parts every image panel shares. beginImagePanel() opens the window and records its place in
// `result`; like ImGui::Begin, it must be paired with ImGui::End() whatever it returns.
bool beginImagePanel(const char* title, bool* open, PanelResult& result);

// The width the image is shown at, the hover readout (the depth sample under the mouse, into
// result.probe) and click-to-zoom, over an image drawn with drawImage().
void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result);

} // namespace dc::ui
