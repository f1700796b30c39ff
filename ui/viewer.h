#pragma once

#include "base/rate_meter.h"
#include "base/rolling_stats.h"
#include "devices/recording/session_recording.h"
#include "devices/session.h"
#include "processing/accumulation_worker.h"
#include "processing/pipeline.h"
#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"
#include "render/rgba_texture.h"
#include "ui/anchors.h"
#include "ui/export_job.h"
#include "ui/panels.h"
#include "ui/settings.h"

#include <chrono>
#include <map>
#include <memory>
#include <string>

namespace dc::ui {

// What a run measured, for summary.json and the benchmark.
struct ViewerSummary {
    std::string source;
    std::uint64_t framesShown = 0; // device frames that reached the panels
    std::uint64_t framesDropped = 0;
    double deviceFps = 0.0;
    double viewerFps = 0.0;
    std::uint64_t pointsDrawn = 0;
    int depthWidth = 0;
    int depthHeight = 0;
    std::vector<processing::StageTiming> stageMedians;
    std::optional<double> latencyMs; // device timestamp to screen, median; none for recordings
};

// The viewer's engine: one session, the processing pipeline, the frame's textures and a render target per
// panel. update() moves the newest frame through them; drawUi() shows the targets in ImGui panels. It owns
// GL objects, so it lives and dies on the GL thread with a context current.
class Viewer {
public:
    static constexpr int kDefaultCloudWidth = 960;
    static constexpr int kDefaultCloudHeight = 720;
    static constexpr int kDefaultCameraWidth = 960; // until a camera panel reports its size
    static constexpr const char* kSnapshotDirectory = "depthcloud-snapshots";

    Viewer(std::unique_ptr<devices::Device> device, Settings settings);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Creates the GL resources and starts the source. A source that cannot start (no depth, bad mode) does
    // not fail the viewer: sourceMessage() says why and the panels say so.
    Status init();
    // Takes the newest frame (waiting up to `wait` for one), processes it and renders the visible panels;
    // the cloud is re-rendered on every call because the view moves. Returns whether a new frame arrived.
    bool update(double timeSeconds, std::chrono::milliseconds wait = std::chrono::milliseconds(0));
    // The ImGui panels, status line and shortcuts (between ImGui::NewFrame and ImGui::Render).
    void drawUi();

    Settings& settings() { return settings_; }
    const Settings& settings() const { return settings_; }
    void resizeCloud(int width, int height);
    void recordUiMilliseconds(double ms) { stage("ui").add(ms); }

    // Writes cloud.png, depth.png, confidence.png and camera.png into `directory`.
    Status savePanels(const std::string& directory) const;
    // Writes the panels as PNGs and the current cloud as cloud.ply (the points drawn, camera frame) into
    // a new directory under `parent` named after the frame; returns that directory.
    Expected<std::string> saveSnapshot(const std::string& parent) const;
    StatusLine statusLine() const;
    ViewerSummary summary() const;
    const std::string& sourceMessage() const { return sourceMessage_; }
    bool sourceRunning() const { return sourceRunning_; }
    const frame::FramePtr& currentFrame() const { return frame_; }
    const render::RenderTarget& cloudTarget() const { return cloudTarget_; }
    const render::RenderTarget& depthTarget() const { return depthTarget_; }
    const render::RenderTarget& confidenceTarget() const { return confidenceTarget_; }
    const render::RenderTarget& cameraTarget() const { return cameraTarget_; }
    const render::RgbaTexture& fogTexture() const { return fogTexture_; }
    const render::RgbaTexture& auraTexture() const { return auraTexture_; }

    // Stops the current source and starts `device` in its place; anchors, accumulated points and temporal
    // state belong to the old source and are dropped.
    void switchSource(std::unique_ptr<devices::Device> device);
    const devices::Session& session() const { return *session_; }
    // Opens the source a --source spec names and switches to it; a bad spec leaves the current source
    // running and says why (returned, logged and shown in the source panel).
    Status openSource(const std::string& spec);
    // Live cameras for the source picker, kept current by whoever watches hotplug.
    void setLiveSources(std::vector<SourceEntry> live) { liveSources_ = std::move(live); }
    // The spec of the source the viewer was created with, for the picker to mark.
    void setSourceSpec(std::string spec) { currentSpec_ = std::move(spec); }

    // The replay's timeline while the source is a replay (null otherwise).
    const std::shared_ptr<devices::replay::ReplayControl>& replayControl() const { return replay_; }
    // Seeks the replay to `index`; frames decoded before the seek are not shown, so the next frame the
    // viewer accepts is exactly the one asked for.
    void seekReplay(std::size_t index);
    void stepReplay(int frames);
    // Starts exporting frames [first, end) of the replay (end 0: to the last) in the background.
    Status startExport(exporting::ExportFormat format, const std::string& directory, std::size_t first,
                       std::size_t end);
    const ExportJob* exportJob() const { return exportJob_.get(); }
    // Records what the source captures into `path` (from the capture thread, never stalling it).
    Status startRecording(const std::string& path);
    Status stopRecording();
    bool recording() const { return recording_ != nullptr; }
    RecordView recordView() const;

    // The depth sample under the mouse in the last drawUi(), on any panel.
    const std::optional<Probe>& hoverProbe() const { return hoverProbe_; }
    // The depth panel's range and colormap as last rendered (the automatic range follows each frame).
    const DepthLegend& depthLegend() const { return legend_; }
    Anchors& anchors() { return anchors_; }
    // The matrix the last cloud was drawn with (depth camera frame to clip space).
    const glm::mat4& cloudViewProjection() const { return cloudViewProjection_; }
    // The panel shown large, or empty.
    const std::string& zoomedPanel() const { return zoomed_; }
    StatsView statsView() const;
    // What the cloud panel says over the view: why the source is not running, or that it is
    // disconnected or stalled (empty while all is well).
    std::string cloudMessage() const;
    const LogStore& log() const { return logs_; }
    const processing::AccumulationWorker& accumulation() const { return accumulation_; }
    // Whether accumulate mode is on and the current frame carries a pose.
    bool accumulating() const;
    void setZoomedPanel(const std::string& title);

private:
    void startSession();
    void drainEvents();
    void acceptFrame(frame::FramePtr frame);
    void renderPanels();
    void renderCloud(double timeSeconds);
    void countPoints();
    void updateLegend();
    void renderEffects(double timeSeconds);
    const frame::DepthData* shownDepth() const;
    bool estimatedConfidence() const;
    void accumulate();
    // The points the cloud shows: the frame's, or in accumulate mode those gathered so far.
    std::uint64_t pointsShown() const;
    ProbeSource probeSource() const;
    void placePanel(const char* title, float x, float y, float w, float h);
    void afterPanel(const char* title, const PanelResult& result);
    void drawCloud(float x, float y, float w, float h);
    void drawSidePanels(float x, float w, float h);
    void drawSourcePicker(float x, float y);
    void drawTimeline(float x, float y, float w);
    void applyTimeline(const TimelineActions& actions);
    void handleReplayKeys();
    void adoptDevice(devices::Device& device);
    void onCloudPointer(const CloudPanelResult& r);
    CloudOverlay cloudOverlay() const;
    processing::Needs needs() const;
    base::RollingStats& stage(const std::string& name) { return stages_[name]; }

    std::unique_ptr<devices::Session> session_;
    Settings settings_;
    processing::Pipeline pipeline_;
    render::FrameTextures textures_;
    render::PointCloudRenderer cloudRenderer_;
    render::PanelRenderer panelRenderer_;
    render::RenderTarget cloudTarget_;
    render::RenderTarget depthTarget_;
    render::RenderTarget confidenceTarget_;
    render::RenderTarget cameraTarget_;
    render::RgbaTexture fogTexture_;
    render::RgbaTexture auraTexture_;
    int cameraShownWidth_ = kDefaultCameraWidth;
    frame::FramePtr frame_;
    std::uint64_t framesShown_ = 0;
    std::uint64_t pointsDrawn_ = 0;
    std::uint64_t countedSequence_ = ~0ull;
    CloudSettings countedWith_;
    float pivotDepthMeters_ = 1.0f;
    glm::mat4 cloudViewProjection_{1.0f};
    DepthLegend legend_;
    Anchors anchors_;
    double lastAnchorTime_ = -1.0;
    std::optional<Probe> hoverProbe_;
    ImVec2 workOrigin_; // the area above the status bar, where panels are laid out and zoomed into
    ImVec2 workSize_;
    std::string zoomed_;
    std::string restoring_; // the panel going back to its place after a zoom, for one frame
    std::map<std::string, std::pair<ImVec2, ImVec2>> panelPlaces_; // title -> (pos, size) before zooming
    std::string state_ = "closed";
    std::string sourceMessage_;
    bool sourceRunning_ = false;
    std::map<std::string, base::RollingStats> stages_;
    base::RollingStats latencyMs_;
    processing::AccumulationWorker accumulation_;
    render::AccumulatedPoints accumulatedPoints_;
    LogStore logs_;
    LogPanelState logPanel_;
    SourcePanelState sourcePanel_;
    std::shared_ptr<devices::replay::ReplayControl> replay_;
    std::uint64_t awaitedSeek_ = 0;
    TimelinePanelState timelineState_;
    std::unique_ptr<ExportJob> exportJob_;
    RecordPanelState recordState_;
    std::unique_ptr<devices::recording::SessionRecording> recording_;
    std::vector<SourceEntry> liveSources_;
    std::string currentSpec_;
    base::RateMeter updates_;
};

} // namespace dc::ui
