#pragma once

#include "engine/demand.h"
#include "engine/instrument.h"
#include "processing/shown_frame.h"
#include "render/view_renderer.h"
#include "ui/anchors.h"
#include "ui/log_store.h"
#include "ui/panels.h"
#include "ui/settings.h"

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

struct ImGuiWindow;

namespace dc::ui {

// What a run measured, for summary.json and the benchmarks.
struct ViewerSummary {
    std::string source;
    engine::FrameCounts frames;
    double uiFps = 0.0; // UI frames drawn per second (with or without a new device frame)
    std::uint64_t uiFramesDrawn = 0;
    std::uint64_t uiFramesKept = 0; // UI frames whose picture was the one on screen already, not drawn
    std::uint64_t pointsDrawn = 0;
    std::string cloudPath; // Viewer::cloudPathText()
    int depthWidth = 0;
    int depthHeight = 0;
    std::vector<engine::StageSummary> stages;
    std::optional<double> latencyMs; // device timestamp to screen, median; none for recordings
};

// The instrument's panels and layout: it states each frame what the UI shows (the engine's demand), shows
// the engine's newest result through the view renderer, and turns input into settings and commands.
// It owns neither the source nor the GL objects (engine::Instrument and render::ViewRenderer do), only
// what the UI itself is made of: settings, layout, anchors, the hover readout, the log.
class Viewer {
public:
    static constexpr int kDefaultCloudWidth = 960;
    static constexpr int kDefaultCloudHeight = 720;
    static constexpr int kDefaultCameraWidth = 960; // until a camera panel reports its size
    static constexpr const char* kSnapshotDirectory = "depthcloud-snapshots";
    // After a settings change the next frame waits this long at most for the result that answers it, so
    // what is drawn matches the settings; work that takes longer shows when it is done.
    static constexpr std::chrono::milliseconds kRedoWait{250};
    // Each new frame moves the automatic depth range this fraction of the way to its own percentiles.
    static constexpr float kRangeFollowFraction = 0.2f;
    // The status line's and stats panel's figures are taken this often at most, and only after something
    // new was drawn: figures that change every frame cannot be read, and a still view whose figures kept
    // changing would be redrawn for them alone.
    static constexpr std::chrono::milliseconds kMeasureInterval{500};
    // Tests on a loaded machine wait longer, so "the next frame shows it" does not depend on the load.
    void setRedoWait(std::chrono::milliseconds wait) { redoWait_ = wait; }

    // States its demand at once: make the viewer before starting the instrument.
    Viewer(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings);

    // Once per UI frame, before drawUi(): states the demand, takes the newest result (waiting up to `wait`
    // for one from a frame not shown yet), uploads it and renders what changed. `timeSeconds` is the time
    // of the call (the view's motion adds the wait to it). Returns whether a new frame's result arrived.
    bool update(double timeSeconds, std::chrono::milliseconds wait = std::chrono::milliseconds(0));
    // The ImGui panels, status line and shortcuts (between ImGui::NewFrame and ImGui::Render).
    void drawUi();
    // What update() drew is on screen now: drawn and shown (`redrawn`), or kept because the frame would have
    // drawn the picture the screen shows already. Counts the device frame it shows, the latency, and the
    // UI frames drawn and kept.
    void presented(bool redrawn = true);

    Settings& settings() { return settings_; }
    const Settings& settings() const { return settings_; }
    engine::Instrument& instrument() { return instrument_; }
    const render::ViewRenderer& renderer() const { return renderer_; }
    void resizeCloud(int width, int height) { renderer_.resizeCloud(width, height); }
    void recordUiMilliseconds(double ms) { instrument_.recordStage("ui", ms); }

    // Writes cloud.png, depth.png, confidence.png (as rendered, at the depth's resolution) and camera.png
    // (the camera's image at its full resolution, where the frame shown has one) into `directory`; returns
    // the names of the files written.
    // The depth and confidence panels are written with every sample of the map, however small they are shown.
    Expected<std::vector<std::string>> savePanels(const std::string& directory);
    // Writes the panels as PNGs and the points drawn as cloud.ply (camera frame) into a directory under
    // `parent` named after the frame, new each time (frame-N, frame-N-2, …); returns that directory. Says
    // where it went, or why it failed, in the log (and so on screen).
    Expected<std::string> saveSnapshot(const std::string& parent);
    // The cloud path the settings and the GL choose, and that with the reason ("CPU splat (software GL)").
    render::CloudPath cloudPath() const;
    std::string cloudPathText() const;
    StatusLine statusLine();
    // How long the last update() waited for the engine's result (benchmarks take it off the frame time).
    double lastWaitMs() const { return lastWaitMs_; }
    // Waits up to `timeout` for the engine's next new frame and keeps it for the next update(), so that a
    // benchmark can time that update (on the CPU and on the GPU) without the wait; false if none came.
    bool awaitFrame(std::chrono::milliseconds timeout);
    ViewerSummary summary();
    // What the hover readout reads: the shown depth, its seen mask or the frame's rig, the infrared.
    ProbeSource probeSource() const;
    StatsView statsView();
    // The figures the status line and the stats panel show now (taken by drawUi at most twice a second).
    const std::optional<StatsView>& shownFigures() const { return measured_; }
    // The result drawn last (null before the first).
    const processing::ShownFramePtr& shown() const { return shown_; }
    // The Quality panel's figures of the frame shown (null while the panel is hidden or before a frame).
    const processing::ShownQuality* quality() const { return shown_ ? shown_->quality.get() : nullptr; }
    // A rectangle drawn on the depth panel (fractions of its image) becomes the Quality panel's region, in
    // the shown depth's pixels.
    void setDrawnRoi(const ImVec4& fractions);
    // The demand stated last.
    const engine::Demand& demand() const { return demand_; }

    // Opens the source a --source spec names; a bad spec leaves the current source running and says why
    // (returned, logged and shown in the source panel).
    Status openSource(const std::string& spec);
    // Opens a file or folder dropped on the window (a recording, a Stray or TUM folder) as the source; one
    // that is none says why, as openSource() does.
    Status openPath(const std::string& path);
    // Live cameras for the source picker, kept current by whoever watches hotplug.
    void setLiveSources(std::vector<SourceEntry> live) { liveSources_ = std::move(live); }

    // The depth sample under the mouse in the last drawUi(), on any panel.
    const std::optional<Probe>& hoverProbe() const { return hoverProbe_; }
    // The depth panel's range and colormap as last rendered (the automatic range follows each frame).
    const DepthLegend& depthLegend() const { return legend_; }
    Anchors& anchors() { return anchors_; }
    // The measurement labels the cloud panel drew last (edge lengths, then the area), on screen.
    const std::vector<LabelBox>& measurementLabels() const { return measurementLabels_; }
    // The matrix the last cloud was drawn with (depth camera frame to clip space).
    const glm::mat4& cloudViewProjection() const { return cloudViewProjection_; }
    // Help > About names this (the tool's version line).
    void setAbout(std::string text) { about_ = std::move(text); }
    // File > Quit was chosen: the window closes as with Ctrl+Q.
    bool quitRequested() const { return quitRequested_; }
    // Whether the frame shown carries the depth sensor's infrared image (the Infrared panel has something).
    bool infraredAvailable() const { return shown_ && shown_->frame && shown_->frame->infrared; }
    // The panel shown large, or empty.
    const std::string& zoomedPanel() const { return zoomed_; }
    void setZoomedPanel(const std::string& title);
    // The default panels in their default places for the window's size now (View > Reset layout).
    void resetLayout();
    // What the cloud panel says over the view: why the source is not running, or that it is disconnected
    // or stalled (empty while all is well).
    std::string cloudMessage();
    const LogStore& log() const { return logs_; }
    // Whether accumulate mode is on and the frame shown carries a pose.
    bool accumulating() const;

private:
    Expected<std::string> writeSnapshot(const std::string& parent);
    engine::Demand demandOf() const;
    void adopt(processing::ShownFramePtr shown);
    void renderCloud(double timeSeconds);
    void updateLegend();
    render::CloudParams cloudParams(double timeSeconds) const;
    // How the depth, confidence and overlay panels are drawn this frame.
    render::PanelParams panelParams() const;
    std::uint64_t pointsShown();
    void placePanel(const char* title, float x, float y, float w, float h);
    void keepInsideWorkArea(const ImGuiWindow* window) const;
    void followLayout();
    std::vector<const char*> rightColumn() const;
    void drawBottomStrip(float x, float y, float w, float h);
    void afterPanel(const char* title, const PanelResult& result);
    void drawControls(float width, float height);
    void toggleRecording();
    void drawCloud(float x, float y, float w, float h);
    void drawSidePanels(float x, float w, float h);
    void drawSourcePicker(float x, float y);
    void drawQuality(float x, float y);
    void drawCameraControls(float x, float y);
    RoiOverlay roiOverlay() const;
    void drawTimeline(devices::replay::ReplayControl& replay, ImVec2 pos, ImVec2 size);
    float drawMenuBar();
    void drawFileMenu();
    void drawHelpMenu();
    void drawHelpWindows();
    void applyTimeline(devices::replay::ReplayControl& replay, const TimelineActions& actions);
    void startExport();
    void handleReplayKeys(devices::replay::ReplayControl& replay);
    void onCloudPointer(const CloudPanelResult& r);
    CloudOverlay cloudOverlay() const;
    void measure();
    StatusLine shownStatusLine();

    engine::Instrument& instrument_;
    render::ViewRenderer& renderer_;
    Settings settings_;
    engine::Demand demand_;
    std::uint64_t demandGeneration_ = 0;
    std::chrono::milliseconds redoWait_ = kRedoWait;
    processing::ShownFramePtr shown_;
    double lastWaitMs_ = 0.0;
    std::optional<processing::ShownFramePtr> awaited_; // taken by awaitFrame, adopted by the next update
    bool presentedShown_ = true;                       // presented() already counted shown_
    int cameraShownWidth_ = kDefaultCameraWidth;
    int dataPanelsShownWidth_ = 0; // the widest the depth panel's image (or the confidence's) is shown
    float pivotDepthMeters_ = 1.0f;
    bool pivotSet_ = false;
    glm::mat4 cloudViewProjection_{1.0f};
    DepthLegend legend_;
    std::optional<processing::DepthRangeMeters> followedRange_; // the automatic range, smoothed
    std::uint64_t followedSequence_ = 0;                        // the frame it last followed
    Anchors anchors_;
    double lastAnchorTime_ = -1.0;
    std::vector<LabelBox> measurementLabels_;
    std::optional<Probe> hoverProbe_;
    ImVec2 workOrigin_; // the area above the status bar, where panels are laid out and zoomed into
    ImVec2 workSize_;
    std::string zoomed_;
    std::string restoring_; // the panel going back to its place after a zoom, for one frame
    std::map<std::string, std::pair<ImVec2, ImVec2>> panelPlaces_; // title -> (pos, size) before zooming
    std::set<std::string> layoutResets_;   // panels still to go back to their default places
    ImVec2 layoutSize_;                    // the window's size the docked panels were laid out for
    std::vector<const char*> dockedShown_; // and the docked panels shown then
    LogStore logs_;
    LogPanelState logPanel_;
    SourcePanelState sourcePanel_;
    CameraControlsState cameraControls_;
    std::optional<std::string> cameraControlsSpec_; // the source cameraControls_ belongs to
    std::optional<std::string> pendingSource_;      // chosen in the frame being drawn, opened at its end
    std::string about_ = "depthcloud";
    bool helpShown_ = false;
    bool aboutShown_ = false;
    bool quitRequested_ = false;
    TimelinePanelState timelineState_;
    RecordPanelState recordState_;
    std::vector<SourceEntry> liveSources_;
    base::RateMeter uiFrames_;
    std::uint64_t uiFramesKept_ = 0;
    std::optional<StatsView> measured_; // the figures on screen (kMeasureInterval)
    std::uint64_t measuredVersion_ = 0; // ViewRenderer::contentVersion() when they were taken
    std::chrono::steady_clock::time_point measuredAt_;
};

} // namespace dc::ui
