#pragma once

#include "devices/device.h"
#include "processing/pipeline.h"
#include "ui/panel_image.h"
#include "ui/settings.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dc::ui {

// Panel titles double as ImGui window identifiers (and so as keys in the saved layout).
inline constexpr const char* kCloudTitle = "Point cloud";
inline constexpr const char* kDepthTitle = "Depth";
inline constexpr const char* kConfidenceTitle = "Confidence";
inline constexpr const char* kCameraTitle = "Camera";
inline constexpr const char* kControlsTitle = "Controls";

struct CloudPanelResult {
    bool viewChanged = false;
    int wantedWidth = 0; // pixel size of the panel's content region: render the next cloud at this size
    int wantedHeight = 0;
};

// The rotating cloud. Left-drag orbits, right- or middle-drag pans, the wheel zooms, a double-click resets
// the manual view. `message` (e.g. an unsupported source) is drawn over the panel when not empty.
CloudPanelResult drawCloudPanel(const PanelImage& image, CloudSettings& cloud, const std::string& message,
                                bool* open);

// Depth in the jet colormap, with the colormap and its range as a legend.
void drawDepthPanel(const PanelImage& image, const DepthRange& range, bool* open);

// Confidence as red (low), green (medium), blue (high); `available` false says the source has none.
void drawConfidencePanel(const PanelImage& image, bool available, bool* open);

// Returns the width in pixels the image is shown at (0 when hidden), so it can be rendered at that size.
int drawCameraPanel(const PanelImage& image, bool* open);

// What the controls need to know but must not change.
struct ControlsContext {
    bool smoothingAvailable = false;
    bool upsamplingAvailable = false;
};

// Every setting; returns whether anything changed.
bool drawControlsPanel(Settings& settings, const ControlsContext& context, bool* open);

struct StatusLine {
    std::string source;
    std::string state;
    std::string message; // an error or warning about the source, shown in red
    double deviceFps = 0.0;
    double viewerFps = 0.0;
    std::uint64_t framesDropped = 0;
    std::uint64_t pointsDrawn = 0;
    std::vector<processing::StageTiming> stageMedians;
};

// A bar along the bottom of the main viewport; returns its height so panels can be laid out above it.
float drawStatusBar(const StatusLine& status);

// Keyboard shortcuts for the common toggles (R rotation, 1/2/3 confidence level, V reset view,
// C show/hide the controls).
// Returns whether any fired. Ignored while a text field has the keyboard.
bool handleShortcuts(Settings& settings);

} // namespace dc::ui
