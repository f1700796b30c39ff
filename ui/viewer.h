#pragma once

#include "ui/companions.h"
#include "ui/log_store.h"
#include "ui/panels.h"
#include "ui/presenter.h"
#include "ui/settings.h"

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>

struct ImGuiWindow;

namespace dc::ui {

// What the hover readout reads of a shown result: its depth, its seen mask or the frame's rig, the infrared.
ProbeSource probeSourceOf(const processing::ShownFramePtr& shown);

// The instrument's panels and layout around a Presenter (which states the demand, takes the engine's newest
// result and draws it through the view renderer): it turns input into settings and commands. It owns
// neither the source nor the GL objects (engine::Instrument and render::ViewRenderer do), only what the UI
// itself is made of: the presenter with the settings and anchors, layout, the hover readout, the log.
class Viewer {
public:
    static constexpr const char* kSnapshotDirectory = "depthcloud-snapshots";
    static constexpr float kRangeFollowFraction = Presenter::kRangeFollowFraction;
    // The status line's and stats panel's figures are taken this often at most, and only after something
    // new was drawn: figures that change every frame cannot be read, and a still view whose figures kept
    // changing would be redrawn for them alone.
    static constexpr std::chrono::milliseconds kMeasureInterval{500};
    // Tests on a loaded machine wait longer, so "the next frame shows it" does not depend on the load.
    void setRedoWait(std::chrono::milliseconds wait) { presenter_.setRedoWait(wait); }

    // States its demand at once: make the viewer before starting the instrument.
    Viewer(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings);
    // settings_ refers into presenter_: a copy would refer into the original's.
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Once per UI frame, before drawUi() (Presenter::update), the companions first so that the fused cloud
    // has their newest frames.
    bool update(double timeSeconds, std::chrono::milliseconds wait = std::chrono::milliseconds(0));
    // The ImGui panels, status line and shortcuts (between ImGui::NewFrame and ImGui::Render).
    void drawUi();
    // What update() drew is on screen now (Presenter::presented).
    void presented(bool redrawn = true) {
        presenter_.presented(redrawn);
        companions_.presented();
    }
    // Opens `spec` beside the main source, its points fused in the cloud (the Sources panel's "Add
    // source"); a bad spec says why, as openSource() does.
    Status addSource(const std::string& spec);
    Companions& companions() { return companions_; }
    // Does what the Sources panel was asked (its buttons); a removal or addition at the next update().
    void applySourcesActions(const SourcesActions& actions);

    Presenter& presenter() { return presenter_; }
    Settings& settings() { return settings_; }
    const Settings& settings() const { return settings_; }
    engine::Instrument& instrument() { return instrument_; }
    const render::ViewRenderer& renderer() const { return renderer_; }
    void resizeCloud(int width, int height) { renderer_.resizeCloud(width, height); }
    void recordUiMilliseconds(double ms) { instrument_.recordStage("ui", ms); }

    Expected<std::vector<std::string>> savePanels(const std::string& directory) {
        return presenter_.savePanels(directory);
    }
    Expected<std::string> saveSnapshot(const std::string& parent) { return presenter_.saveSnapshot(parent); }
    std::string cloudPathText() const { return presenter_.cloudPathText(); }
    StatusLine statusLine();
    double lastWaitMs() const { return presenter_.lastWaitMs(); }
    bool awaitFrame(std::chrono::milliseconds timeout) { return presenter_.awaitFrame(timeout); }
    ViewerSummary summary() { return presenter_.summary(); }
    // What the hover readout reads: the shown depth, its seen mask or the frame's rig, the infrared.
    ProbeSource probeSource() const;
    // The image panels' source (SourceTabs): 0 the main source, N the Nth further source.
    std::size_t& panelSource() { return panelSource_; }
    StatsView statsView();
    // The figures the status line and the stats panel show now (taken by drawUi at most twice a second).
    const std::optional<StatsView>& shownFigures() const { return measured_; }
    const processing::ShownFramePtr& shown() const { return presenter_.shown(); }
    // The Quality panel's figures of the frame shown (null while the panel is hidden or before a frame).
    const processing::ShownQuality* quality() const { return shown() ? shown()->quality.get() : nullptr; }
    // The Quality panel's figures of every frame it showed since the source opened or Clear was pressed.
    const exporting::QualityLog& qualityLog() const { return quality_.log; }
    // The Quality panel's map pixel under the mouse in the last frame drawn, as the panel read it out.
    const std::optional<QualityMapHover>& qualityMapHover() const { return qualityMapHover_; }
    // Writes them (the panel's "Save CSV + JSON"): a new folder under `parent`, logged; returns it.
    Expected<std::string> saveQualityFigures(const std::string& parent);
    // A rectangle drawn on the depth panel (fractions of its image) becomes the Quality panel's region, in
    // the shown depth's pixels.
    void setDrawnRoi(const ImVec4& fractions);
    void setDrawnPolygon(const std::vector<ImVec2>& fractions);
    const engine::Demand& demand() const { return presenter_.demand(); }

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
    const DepthLegend& depthLegend() const { return presenter_.depthLegend(); }
    Anchors& anchors() { return presenter_.anchors(); }
    // The measurement labels the cloud panel drew last (edge lengths, then the area), on screen.
    const std::vector<LabelBox>& measurementLabels() const { return measurementLabels_; }
    const glm::mat4& cloudViewProjection() const { return presenter_.cloudViewProjection(); }
    // The companion whose gizmo the Cloud panel draws (the Sources panel's Gizmo toggle), and the gizmo as
    // it was last drawn: where that source sat and the matrix from the world to the cloud's clip space.
    const std::optional<std::size_t>& gizmoSource() const { return sourcesPanel_.gizmo; }
    const CloudGizmo& cloudGizmo() const { return cloudGizmo_; }
    // Help > About names this (the tool's version line).
    void setAbout(std::string text) { about_ = std::move(text); }
    // File > Quit was chosen: the window closes as with Ctrl+Q.
    bool quitRequested() const { return quitRequested_; }
    // Whether the frame shown carries the depth sensor's infrared image (the Infrared panel has something).
    bool infraredAvailable() const { return shown() && shown()->frame && shown()->frame->infrared; }
    // The panel shown large, or empty.
    const std::string& zoomedPanel() const { return zoomed_; }
    void setZoomedPanel(const std::string& title);
    // The default panels in their default places for the window's size now (View > Reset layout).
    void resetLayout();
    // What the cloud panel says over the view: why the source is not running, or that it is disconnected
    // or stalled (empty while all is well).
    std::string cloudMessage();
    const LogStore& log() const { return logs_; }
    bool accumulating() const { return presenter_.accumulating(); }

private:
    void placePanel(const char* title, float x, float y, float w, float h);
    void keepInsideWorkArea(const ImGuiWindow* window) const;
    void followLayout();
    std::vector<std::string_view> rightColumn() const;
    void drawBottomStrip(float x, float y, float w, float h);
    void afterPanel(const char* title, const PanelResult& result);
    void drawControls(float width, float height);
    void toggleRecording();
    void drawCloud(float x, float y, float w, float h);
    bool placeGizmo();
    void drawSidePanels(float x, float w, float h);
    void drawSourcePicker(float x, float y);
    void drawQuality(float x, float y);
    void drawCameraControls(float x, float y);
    void drawSources(float x, float y);
    void reopenInMode(const Expected<std::string>& spec);
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
    Presenter presenter_;
    Settings& settings_ = presenter_.settings();
    double lastAnchorTime_ = -1.0;
    std::vector<LabelBox> measurementLabels_;
    std::optional<Probe> hoverProbe_;
    ImVec2 workOrigin_; // the area above the status bar, where panels are laid out and zoomed into
    ImVec2 workSize_;
    std::string zoomed_;
    std::string restoring_; // the panel going back to its place after a zoom, for one frame
    std::map<std::string, std::pair<ImVec2, ImVec2>> panelPlaces_; // title -> (pos, size) before zooming
    std::set<std::string> layoutResets_;        // panels still to go back to their default places
    ImVec2 layoutSize_;                         // the window's size the docked panels were laid out for
    std::vector<std::string_view> dockedShown_; // and the docked panels shown then
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
    QualityPanelState quality_;
    Companions companions_; // after presenter_: its presenters draw with their own renderers
    SourcesPanelState sourcesPanel_;
    std::size_t panelSource_ = 0; // whose pictures the image panels show: 0 the main source, N companion N-1
    CloudGizmo cloudGizmo_;
    // Chosen in the Sources panel during a frame, done at the next update(): the frame's draw lists may
    // still show a companion's panel.
    std::optional<std::string> pendingAddition_;
    std::optional<std::size_t> pendingRemoval_;
    std::optional<QualityMapHover> qualityMapHover_; // the Quality panel's map pixel under the mouse
    std::optional<StatsView> measured_;              // the figures on screen (kMeasureInterval)
    std::uint64_t measuredVersion_ = 0;              // ViewRenderer::contentVersion() when they were taken
    std::chrono::steady_clock::time_point measuredAt_;
};

} // namespace dc::ui
