#pragma once

#include "ui/panels.h"

namespace dc::ui {

// The parts every image panel shares. beginImagePanel() opens the window and records its place in
// `result`; whatever it returns, it must be paired with endImagePanel().
//
// The panel's images are opaque, so the window's background is drawn around the image rather than under
// it: on a software rasteriser a fill under each image is a panel-sized pass of every frame for pixels
// the image then replaces.
bool beginImagePanel(const char* title, bool* open, PanelResult& result);
// The row that picks the source the image panels show (nothing with one source).
void drawSourceTabs(const SourceTabs& tabs);
// Draws the window's background everywhere but `opaque` (the image drawImage() placed, or an empty rect
// where none was) and ends the window.
void endImagePanel(const ImageRect& opaque);

// The width the image is shown at, the hover readout (the depth sample under the mouse, into
// result.probe) and click-to-zoom, over an image drawn with drawImage(). With `dragDraws`, a left drag
// across the image draws a rectangle (into result.drawnRect) and only a click that does not drag zooms; with
// Shift held as it starts, the drag draws a lasso (into result.drawnPolygon).
void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result,
                       bool dragDraws = false);

// Outlines a closed polygon of the image (vertices as fractions of it), clipped to the part shown.
void outlineImagePolygon(const ImageRect& shown, const std::vector<ImVec2>& fractions, ImU32 colour);
// Outlines a rectangle of the image (fractions: left, top, right, bottom), clipped to the part shown.
void outlineImageRect(const ImageRect& shown, ImVec4 fractions, ImU32 colour);

// interactWithImage() on a panel that shows the Quality panel's region: outlined over the image, and a
// left drag draws a new one while it can be drawn.
void interactWithImage(const ImageRect& shown, const ProbeSource& source, PanelResult& result,
                       const RoiOverlay& roi);

} // namespace dc::ui
