#pragma once

#include "devices/replay/replay_device.h"
#include "devices/sensor_controls.h"
#include "engine/instrument.h"
#include "exporting/quality_log.h"
#include "processing/infrared_image.h"
#include "processing/pipeline.h"
#include "processing/rigid_alignment.h"
#include "processing/shown_frame.h"
#include "render/render_target.h"
#include "ui/companions.h"
#include "ui/depth_legend.h"
#include "ui/file_picker.h"
#include "ui/fused_cloud.h"
#include "ui/gizmo.h"
#include "ui/log_store.h"
#include "ui/panel_image.h"
#include "ui/probe.h"
#include "ui/settings.h"
#include "ui/source_settings.h"

#include <optional>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dc::ui {

// Panel titles double as ImGui window identifiers (and so as keys in the saved layout).
inline constexpr const char* kCloudTitle = "Point cloud";
inline constexpr const char* kDepthTitle = "Depth";
inline constexpr const char* kConfidenceTitle = "Confidence";
inline constexpr const char* kCameraTitle = "Camera";
inline constexpr const char* kInfraredTitle = "Infrared";
inline constexpr const char* kControlsTitle = "Controls";

inline constexpr const char* kStatsTitle = "Stats";
inline constexpr const char* kLogTitle = "Log";
inline constexpr const char* kSourceTitle = "Source";
inline constexpr const char* kTimelineTitle = "Timeline";
// Every toast's window name starts so (drawToasts), which puts them in front of the panels.
inline constexpr const char* kToastPrefix = "##toast";
inline constexpr const char* kFogTitle = "Fog";
inline constexpr const char* kAuraTitle = "Aura";
inline constexpr const char* kQualityTitle = "Quality";
inline constexpr const char* kCameraControlsTitle = "Camera controls";
inline constexpr const char* kTimingTitle = "Timing";
inline constexpr const char* kSourcesTitle = "Sources";

// What every image panel reports back: the window's place (to restore it after a zoom), a request to
// open it large or bring it back (a click on a 2D panel, the zoom button on the cloud), and the depth
// sample under the mouse for the readout.
struct PanelResult {
    bool visible = false;
    ImVec2 windowPos;
    ImVec2 windowSize;
    bool toggleZoom = false;
    std::optional<Probe> probe;
    // The width in pixels the whole image is shown at (a filled panel shows a crop of a wider image); 0
    // when none is shown. The GL thread draws the image at this size rather than at the data's own.
    int shownWidth = 0;
    // A rectangle dragged across the image (the depth panel's region of interest), as fractions of the
    // whole image: (left, top, right, bottom).
    std::optional<ImVec4> drawnRect;
    // A lasso drawn with Shift held (the region as a polygon): its vertices, fractions of the whole image, at
    // least 3.
    std::optional<std::vector<ImVec2>> drawnPolygon;
};

// The Quality panel's region on an image panel that covers the depth map's field of view (depth,
// confidence, infrared, a single camera's image): outlined there and, while it can be drawn, a left drag
// across the image draws a new one (a click that does not drag still zooms), with Shift held a lasso.
struct RoiOverlay {
    bool drawable = false;
    std::optional<ImVec4> outline; // the region measured, fractions of the image: (left, top, right, bottom)
    std::vector<ImVec2> polygon;   // a polygon region's vertices, fractions of the image: outlined instead
    PanelImage causes;             // the region's missing samples coloured by cause, laid over the outline
};

// A mark drawn over the cloud: an anchor (a label at a point) or a measured segment between two.
struct CloudOverlay {
    std::vector<ImVec2> anchors; // in the cloud image, fractions of its size
    // (first anchor of the edge, label); the edge from the last anchor back to the first closes a polygon
    std::vector<std::pair<int, std::string>> segments;
    std::string summary; // the polygon's area, drawn at its centroid
    // The Quality panel's region on the measured surface: polylines in the cloud image, fractions of its
    // size, broken where the region's border has no point.
    std::vector<std::vector<ImVec2>> roiOutline;
};

// A measurement label as drawn on screen: its box and the point it labels (an edge's midpoint, the
// polygon's centroid).
struct LabelBox {
    ImVec2 min;
    ImVec2 max;
    ImVec2 anchor;
};

// Boxes of `sizes` centred on `anchors`, each moved away from its anchor (along `away`, a unit direction per
// label) in steps until it overlaps none placed before it; the first stays where it is.
std::vector<LabelBox> placeLabels(const std::vector<ImVec2>& anchors, const std::vector<ImVec2>& sizes,
                                  const std::vector<ImVec2>& away);

struct CloudPanelResult {
    PanelResult panel;
    bool viewChanged = false;
    int wantedWidth = 0; // pixel size of the panel's content region: render the next cloud at this size
    int wantedHeight = 0;
    std::optional<ImVec2> hoverPixels; // the mouse over the cloud, in cloud-image pixels
    std::optional<ImVec2> clickPixels; // a left click (not a drag) on the cloud, in cloud-image pixels
    bool doubleClicked = false;        // the view was reset by a double-click
    std::vector<LabelBox> labels;      // the measurement labels drawn, on screen
    // What dragging the gizmo's handle did this frame: a world-frame transform to compose onto the
    // source's correction.
    std::optional<frame::RigidTransform> gizmoStep;
};

// The gizmo of the source the Sources panel chose, over the cloud: where its camera sits in the world and
// how the world reaches the panel (the viewer sets these each frame), and what the mouse does with it (the
// panel keeps these between frames).
struct CloudGizmo {
    glm::dvec3 originWorld{0.0};
    glm::dmat4 worldToClip{1.0}; // the cloud's view-projection after the world to the main camera
    std::optional<GizmoHandle> hovered;
    std::optional<GizmoHandle> held; // pressed on and not yet released: the gizmo owns the left button
    glm::dvec2 heldAt{0.0};          // where the last drag step left the mouse, in panel pixels
};

// The rotating cloud. Left-drag orbits, right- or middle-drag pans, the wheel zooms, a double-click resets
// the manual view, a click is reported (anchors). `message` (e.g. an unsupported source) is drawn over the
// panel when not empty. The cloud reaches the window as a copy of `picture`'s pixels, not a textured quad:
// on a software GL that is the cheaper of the two by far, and it is the same picture. With a `gizmo`, its
// arrows and rings are drawn over the cloud; a left drag that starts on one moves or turns the source
// (CloudPanelResult::gizmoStep) instead of orbiting.
CloudPanelResult drawCloudPanel(const render::RenderTarget& picture, CloudSettings& cloud,
                                const CloudOverlay& overlay, const std::string& message, bool zoomed,
                                bool* open, CloudGizmo* gizmo = nullptr);

// An image laid over a panel's own at an opacity (none: an empty image).
struct PanelOverlay {
    PanelImage image;
    float opacity = 0.5f;
};

// With several sources open, the image panels show one source's pictures at a time: a row of its names
// over the image picks which (the same choice for every image panel). Empty: one source, no row.
struct SourceTabs {
    std::vector<std::string> names; // "Source 1" (the main source), "Source 2", ...
    std::size_t* selected = nullptr;
};

// Depth in the chosen colormap, with the colormap and its range as a legend, and the camera's colour
// aligned to it laid over it when `colour` has an image.
PanelResult drawDepthPanel(const PanelImage& image, const PanelOverlay& colour, const DepthLegend& legend,
                           const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                           const SourceTabs& tabs = {});

// Confidence as red (low), green (medium), blue (high); `available` false says the source has none,
// `estimated` that it was estimated from the depth because the camera reports none.
PanelResult drawConfidencePanel(const PanelImage& image, bool available, bool estimated,
                                const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                                const SourceTabs& tabs = {});

// The depth sensor's infrared image in gray, contrast-stretched (the engine's 1st-99th percentile).
// The infrared image with the stretch it was drawn with (raw intensities to black..white) as a legend.
PanelResult drawInfraredPanel(const PanelImage& image, const processing::IntensityRange& range,
                              const ProbeSource& probe, const RoiOverlay& roi, bool* open);

// The camera image, fitted or filling the panel, optionally with the depth laid over it: the depth panel's
// image for a single camera, the depth aligned to the colour image for two sensors.
// A two-sensor camera's image does not share the depth map's field of view: it gets no region (`roi` empty).
PanelResult drawCameraPanel(const PanelImage& image, const PanelImage& depthOverlay, const CameraView& view,
                            const ProbeSource& probe, const RoiOverlay& roi, bool* open,
                            const SourceTabs& tabs = {});

// The folder field's text while it is edited (RecordSettings::directory follows it).
struct RecordPanelState {
    std::array<char, 512> directory{};
    bool editing = false; // the field had the keyboard last frame: the buffer leads, not the settings
};

inline constexpr const char* kRecordButtonId = "###record";

// The record button (inside the controls panel) with where and how takes are stored; returns true when the
// button was pressed. The button keeps its place and size whether it says Record or Stop.
bool drawRecordControls(const engine::RecordingStatus& view, RecordSettings& settings,
                        RecordPanelState& state);

// What the controls need to know but must not change.
struct ControlsContext {
    bool smoothingAvailable = false;
    bool upsamplingAvailable = false;
    std::size_t anchorCount = 0;
    bool hasPose = false; // accumulate needs world coordinates
    std::size_t accumulatedPoints = 0;
    std::string cloudPath;         // the path drawing the cloud, and why
    int cloudDecimation = 1;       // the factor in use
    std::uint64_t cloudPoints = 0; // points the cloud draws
    engine::RecordingStatus record;
    RecordPanelState* recordState = nullptr;
    bool infraredAvailable = false; // the source delivers infrared: the Infrared panel can be shown
};

// What the controls ask for beyond settings.
struct ControlsResult {
    bool changed = false; // any setting
    bool undoAnchor = false;
    bool clearAnchors = false;
    bool clearAccumulation = false;
    bool toggleRecording = false;
    bool snapshot = false;
    bool resetLayout = false;
};

// Every setting.
ControlsResult drawControlsPanel(Settings& settings, const ControlsContext& context, bool* open);
// The Controls panel's processing group (depth shown, smoothing, upsampling) for `p`, wherever it is
// drawn (a further source's own processing in the Sources panel); returns whether anything changed.
bool processingControls(processing::ProcessingSettings& p, const ControlsContext& context);

struct StatusLine {
    std::string source;
    std::string state;
    std::string message; // an error or warning about the source, shown in red
    engine::FrameCounts frames;
    double uiFps = 0.0;
    std::uint64_t pointsDrawn = 0;
    std::string cloudPath; // e.g. "CPU splat (software GL)"
    std::vector<processing::StageTiming> stageMedians;
    std::optional<double> latencyMs; // median device timestamp to screen; none when clocks differ
    // A two-sensor camera's calibration in use, or that its colours are not registered; empty for one camera.
    std::string calibration;
    std::string recording; // while recording: "REC 0:12 | 360 frames | 34.5 MB", first and in red
};

struct StageHistory {
    std::string name;
    double medianMs = 0.0;
    double maxMs = 0.0;
    std::vector<float> history; // the last few seconds, oldest first
};

struct StatsView {
    engine::FrameCounts frames;
    double uiFps = 0.0;
    std::uint64_t pointsDrawn = 0;
    std::optional<double> latencyMs; // median device timestamp to screen; none when clocks differ
    double residentMebibytes = 0.0;
    std::vector<StageHistory> stages;
};

// Rates, drops, latency, memory and each stage's median and maximum with a plot of its recent history.
void drawStatsPanel(const StatsView& stats, bool* open);

struct LogPanelState {
    int minLevel = static_cast<int>(LogLevel::Info);
    ImGuiTextFilter filter;
};

// The log's recent messages, filtered by level and text.
void drawLogPanel(const std::vector<LogEntry>& entries, LogPanelState& state, bool* open);

// Recent warnings and errors as small notes in the bottom-right corner, above `bottomMargin` pixels.
void drawToasts(const std::vector<LogEntry>& entries, float bottomMargin);

struct SourceEntry {
    std::string label;
    std::string spec; // what --source takes
};

// What the source picker offers: live cameras (kept current by hotplug), recent sources, built-in ones.
struct SourceList {
    std::string current;
    std::vector<SourceEntry> live;
    std::vector<SourceEntry> recent;
    std::vector<SourceEntry> builtIn;
};

struct SourcePanelState {
    std::array<char, 512> spec{};
    std::string error; // why the last attempt to open a source failed
    FilePickerState files;
    bool filesOpen = false; // the file picker's window, opened by Browse
};

// The source picker, with a file picker for recordings and captures (Browse); returns the spec the user
// chose to open.
std::optional<std::string> drawSourcePanel(const SourceList& list, SourcePanelState& state, bool* open);

struct TimelineView {
    devices::replay::ReplayStatus status;
    bool exporting = false;
    std::size_t exportDone = 0;
    std::size_t exportTotal = 0;
    std::vector<TimelineSourceRow> sources; // the further sources', while there are any
};

// The timeline's own edits: the range to export, its format and where it goes.
struct TimelinePanelState {
    std::size_t rangeStart = 0;
    std::size_t rangeEnd = 0; // exclusive; 0 = to the last frame
    int format = 0;           // exporting::ExportFormat
    std::array<char, 512> outDirectory{"depthcloud-export"};
};

// What the user asked the replay to do this frame.
struct TimelineActions {
    std::optional<std::size_t> seekIndex;
    int step = 0;
    std::optional<bool> play;
    std::optional<bool> loop;
    std::optional<double> speed;
    bool exportRange = false;
    bool cancelExport = false;
};

// Play/pause, step, first/last, loop, speed, a frame scrubber with the time, under it a thin row per further
// source with its frames and the one it shows, and the range export; `flags` dock it (the viewer places it
// as a strip).
TimelineActions drawTimelinePanel(const TimelineView& view, TimelinePanelState& state, bool* open,
                                  ImGuiWindowFlags flags = 0);

// Seed 002's fog and seed 004's aura, each with its own controls above the image; return whether a
// setting changed.
bool drawFogPanel(const PanelImage& image, processing::FogSettings& fog, bool* open);
bool drawAuraPanel(const PanelImage& image, processing::AuraSettings& aura, bool* open);

// What the Quality panel keeps between frames: every shown frame's figures (for the plot and for saving),
// the figure plotted, and where the last save went.
struct QualityPanelState {
    exporting::QualityLog log;
    exporting::QualityFigure plotted = exporting::QualityFigure::PlaneFitRmsMm;
    std::string savedTo;
};
// A pixel of the Quality panel's map under the mouse: its place in the region and its value.
struct QualityMapHover {
    int x = 0; // region pixels from its left
    int y = 0;
    float value = 0.0f; // in the map's unit; NaN where the pixel has none
};
// What the Quality panel asked for this frame.
struct QualityPanelResult {
    bool settingsChanged = false;
    bool save = false;  // write the kept figures (CSV and JSON)
    bool clear = false; // forget them
    std::optional<QualityMapHover> mapHover;
};
// The depth-quality figures of the frame shown over the region of interest (null: none measured yet),
// with the presets and settings that choose them, the per-pixel map chosen (`map`: the frame's
// ShownQuality::map as a texture; empty when it has none), and the kept figures' save and clear buttons.
QualityPanelResult drawQualityPanel(const processing::ShownQuality* quality, QualitySettings& settings,
                                    QualityPanelState& state, const PanelImage& map, bool* open);

// What the Camera controls panel keeps between frames: the source's controls (null: it has none), their
// values as last read, and what the driver last refused.
struct CameraControlsState {
    std::shared_ptr<devices::SensorControls> controls;
    std::vector<devices::SensorControlNode> nodes;
    double readAtSeconds = -1e9;
    std::string message;                                   // the last refusal, shown until a value is set
    std::vector<std::string> refused;                      // refusals not yet logged (the viewer takes them)
    std::optional<std::vector<devices::StreamMode>> modes; // the depth node's, read once
    std::optional<devices::StreamMode> chosenMode;         // chosen this frame: the viewer reopens the source
    std::string modeShown;                                 // what the mode list shows as current
    std::optional<std::vector<devices::StreamMode>> colorModes; // the same for the colour node
    std::optional<devices::StreamMode> chosenColorMode;
    std::string colorModeShown;
};
// Every control of each node with its type's widget: a change is set at once and read back; an inactive
// control (an auto control decides it) is greyed; "Reset to defaults" per node. Above them, the depth and
// colour nodes' modes: one chosen is left in state.chosenMode or state.chosenColorMode.
void drawCameraControlsPanel(CameraControlsState& state, double nowSeconds, bool* open);

// One source of the fused cloud as the Sources panel lists it: the main source (no look: it defines the
// world's view) or a companion.
struct SourceRow {
    std::string name;
    std::string state; // SourceState::text()
    engine::FrameCounts frames;
    std::optional<processing::OverlapFigure> overlap; // with the main source, companions only
    std::optional<double> skewMs;                     // its frame's time less the main source's
    std::optional<double> skewMedianMs;               // the same over the last frames
    bool paired = true;            // within the pairing tolerance of the main source's frame, so drawn
    CompanionLook* look = nullptr; // the companion's; null for the main source
    PanelImage depth;              // its depth panel as last drawn
    PanelImage camera;             // its camera panel (empty: no camera image)
    SourceSettings* own = nullptr; // the companion's processing; null for the main source
};

struct SourcesPanelState {
    std::array<char, 512> spec{};
    std::string message;              // the last addition's or refinement's outcome
    std::optional<std::size_t> gizmo; // the companion whose gizmo the Cloud panel draws
};

// What the user asked of the Sources panel this frame (companions by their index among the companions).
struct SourcesActions {
    std::optional<std::string> add;
    std::optional<std::size_t> remove;
    std::optional<std::size_t> refine;
    std::optional<std::size_t> resetPlacement;
    bool savePlacements = false;
};

// Every source fused in the cloud: its state and frames (shown, dropped, delivered: its own), its depth
// and camera panels, and for each companion its visibility, tint, overlap figure with the main source, ICP
// refinement and removal; "Add source" opens another; "Save placements" writes every source's placement.
// `pairingToleranceMs` is SourcesSettings'.
SourcesActions drawSourcesPanel(const std::vector<SourceRow>& rows, SourcesPanelState& state,
                                float& pairingToleranceMs, bool* open);

// Per stream the frame intervals' histogram and the timestamps' source, the latency from arrival (and
// from the sensor, where its clock is this machine's) to the screen, and every lost frame counted where it
// was lost. With further sources, each one's skew from the main source: now, its median and range, a
// histogram with the pairing tolerance drawn on it, and how many were beyond it.
void drawTimingPanel(const engine::TimingSummary& timing, bool* open,
                     const std::vector<SourceSkew>& sources = {});

// A bar along the bottom of the main viewport; returns its height so panels can be laid out above it.
float drawStatusBar(const StatusLine& status);

// Keyboard shortcuts for the common toggles (R rotation, 1/2/3 confidence level, V reset view,
// C / S / L show or hide the controls, stats and log panels).
// Returns whether any fired. Ignored while a text field has the keyboard.
bool handleShortcuts(Settings& settings);

} // namespace dc::ui
