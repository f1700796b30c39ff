#pragma once

#include "base/expected.h"
#include "frame/frame.h"
#include "processing/pipeline.h"
#include "render/colormap.h"
#include "render/orbit_camera.h"
#include "render/point_cloud_renderer.h"

#include <cstddef>
#include <string>
#include <vector>

namespace dc::ui {

struct PanelVisibility {
    bool cloud = true;
    bool depth = true;
    bool confidence = true;
    bool camera = true;
    bool controls = true;
    bool stats = false;
    bool log = false;
    bool source = false;
    bool timeline = true; // shown while the source is a replay
    bool fog = false;
    bool aura = false;
    bool infrared = false;       // drawn only while the source delivers infrared
    bool quality = false;        // the depth-quality figures (measured only while it is shown)
    bool cameraControls = false; // a live camera's V4L2 controls
    bool timing = false;         // frame intervals, latencies and where lost frames were lost
    bool sources = false;        // every source fused in the cloud: add, place, refine, remove
};

// Which cloud path draws (render::CloudPath): automatic picks the CPU splat on software GL.
enum class CloudPathChoice { Automatic, Points, Splat };
inline constexpr int kMaxDecimation = 8;

struct CloudSettings {
    frame::Confidence minConfidence = frame::Confidence::Low; // points below are not drawn
    float pointSizePixels = 2.0f;
    bool fillGaps = true;    // points grow to their sample's footprint (render::CloudParams::fillGaps)
    float nearMeters = 0.1f; // points nearer than this are not drawn (the sample drops the nearest too)
    render::PointColoring coloring = render::PointColoring::Camera;
    CloudPathChoice path = CloudPathChoice::Automatic;
    // Each decimation x decimation cell of the depth becomes its nearest point; 0 fits the points to the
    // panel's pixels (never more points than the panel can show).
    int decimation = 0;
    render::AutoMotion motion;
    render::OrbitView orbit;
};

struct DepthRange {
    float minMeters = 0.0f; // the fixed range: the sample's 0 to 2.5 m
    float maxMeters = 2.5f;
    // The colours follow the data (the 2nd to 98th depth percentiles, smoothed over time) unless the user
    // fixes the range (one click): a fixed 0 to 2.5 m paints most of a room-scale capture one colour.
    bool automatic = true;
    render::Colormap colormap = render::Colormap::Jet;
};

// Several sources fused in one cloud: a further source's frame is drawn only while its time is within this
// of the first source's frame (0: each source's newest frame, however far apart).
struct SourcesSettings {
    float pairingToleranceMs = 0.0f;
};

// Accumulate mode (posed sources only): world points of every frame within a budget.
struct AccumulateSettings {
    bool enabled = false;
    int budgetThousands = 1000;
    float voxelMillimeters = 5.0f;
};

// How the record button stores its takes: numbered files in `directory`, the camera image as JPEG (the
// default: a tenth of the size of the raw image, and the rate a busy machine keeps up with) or as captured.
// Depth and confidence are always lossless.
struct RecordSettings {
    std::string directory = ".";
    bool jpegColor = true;
    int jpegQuality = 90; // 1 .. 100
};

// The camera panel fits the whole image (letterboxed) or fills the panel and crops, as the sample's
// display transform does; the depth can be laid over it.
struct CameraView {
    bool fill = false;
    bool depthOverlay = false;
    float overlayOpacity = 0.5f;
};

// The depth panel can have the camera's colour, aligned to the depth, laid over it.
struct DepthView {
    bool colourOverlay = false;
    float overlayOpacity = 0.5f;
};

// The Quality panel's region of interest and how its samples are judged (engine::QualityDemand).
inline constexpr int kQualityRoiPresets[] = {20, 40, 60, 80};
inline constexpr std::size_t kMaxPolygonVertices = 256; // a lasso's, as drawn or read from the file
struct QualitySettings {
    int roiPercent = 40; // a centred preset (kQualityRoiPresets); 0: the rectangle below (or the polygon)
    int roiX = 0;        // the rectangle, in the shown depth's pixels (drawn on the depth panel)
    int roiY = 0;
    int roiWidth = 0;
    int roiHeight = 0;
    int windowFrames = 30;      // frames the temporal and spatial noise are measured over
    float groundTruthMm = 0.0f; // the target's true distance, for the Z accuracy; 0: none entered
    float nearMeters = 0.0f;    // samples outside [near, far] count as out of range
    float farMeters = 10.0f;
    float flyingThresholdMm = 50.0f; // processing::QualityParams::flyingThresholdMeters, in mm
    float baselineMm = 0.0f; // a stereo camera's baseline, for subpixel RMS and the expected noise; 0: none
    float designSubpixelRms = 0.08f; // the camera's design subpixel accuracy, pixels (the expected noise)
    bool causeOverlay = true;        // the region's missing samples coloured by cause on the image panels
    int map = 0;            // the per-pixel map shown: an index into processing::kQualityMaps (0: none)
    bool alignment = false; // the colour-to-depth edge alignment (registers the colour every frame)
    // A lasso drawn instead of the rectangle (Shift + drag): x, y, x, y, ... in the shown depth's pixel
    // coordinates, at least 3 vertices; empty: the rectangle. A plain drag or a preset clears it.
    std::vector<float> polygon;
};

// Where the window was and how large, in screen coordinates, as it was closed (width 0: never saved).
struct WindowPlacement {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    bool maximized = false;
};

// Everything the user can set; plain data, edited by the panels, persisted between runs.
struct Settings {
    PanelVisibility panels;
    WindowPlacement window;
    CloudSettings cloud;
    DepthRange depthRange;
    CameraView camera;
    DepthView depthView;
    AccumulateSettings accumulate;
    SourcesSettings sources;
    RecordSettings record;
    QualitySettings quality;
    processing::ProcessingSettings processing;
    std::vector<std::string> recentSources; // newest first, at most kMaxRecentSources
};

inline constexpr std::size_t kMaxRecentSources = 8;

// Moves `source` to the front of the recent list (adding it if new) and trims the list.
void rememberSource(Settings& settings, const std::string& source);

// Puts every field back into its valid range (a hand-edited or old settings file may hold anything).
void sanitize(CloudSettings& cloud);
void sanitize(QualitySettings& quality);
void sanitize(Settings& settings);

std::string settingsToJson(const Settings& settings);
// Reads what it can: unknown keys are ignored, missing or mistyped ones keep their defaults, and the
// result is sanitized. A file that is not JSON at all gives an Error naming the parse failure.
Expected<Settings> settingsFromJson(const std::string& text);

// One `--set SECTION.KEY=VALUE`: the field of the settings file with that name (a top-level one by KEY
// alone) takes VALUE, read as JSON (true, 2.5, [0.1, 0.2, 0.3]) or else as a string. An unknown name, a
// value of another type or one out of the field's range is an Error naming it; the settings are then as
// they were.
Status applySetting(Settings& settings, const std::string& assignment);

// $XDG_CONFIG_HOME/depthcloud, else $HOME/.config/depthcloud, else the current directory.
std::string configDirectory();

} // namespace dc::ui
