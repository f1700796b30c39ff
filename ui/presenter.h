#pragma once

#include "base/rate_meter.h"
#include "engine/demand.h"
#include "engine/instrument.h"
#include "processing/rigid_alignment.h"
#include "processing/shown_frame.h"
#include "render/view_renderer.h"
#include "ui/anchors.h"
#include "ui/depth_legend.h"
#include "ui/fused_cloud.h"
#include "ui/settings.h"

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc::ui {

class Companions;

// What a run measured, for summary.json and the benchmarks.
struct ViewerSummary {
    std::string source;
    engine::FrameCounts frames;
    double uiFps = 0.0; // UI frames drawn per second (with or without a new device frame)
    std::uint64_t uiFramesDrawn = 0;
    std::uint64_t uiFramesKept = 0; // UI frames whose picture was the one on screen already, not drawn
    std::uint64_t pointsDrawn = 0;
    std::string cloudPath; // Presenter::cloudPathText()
    int depthWidth = 0;
    int depthHeight = 0;
    std::vector<engine::StageSummary> stages;
    std::optional<double> latencyMs; // device timestamp to screen, median; none for recordings
    // A companion's overlap consistency figure with the main source (none for the main source).
    std::optional<processing::OverlapFigure> overlap;
    std::optional<double> skewMs; // a companion's frame's time less the main source's, median over the run
};

// The instrument presented without ImGui: the settings stated as the engine's demand each frame, the
// engine's newest result taken, uploaded and drawn through the view renderer, the automatic depth range
// followed, frames shown counted, panels and snapshots written. The window's Viewer draws its panels
// around one; the headless run uses one alone. It lives in ui/ because it is where the settings meet both
// the engine (the demand) and the renderer (what is drawn), and nothing here includes ImGui.
class Presenter {
public:
    static constexpr int kDefaultCloudWidth = 960;
    static constexpr int kDefaultCloudHeight = 720;
    static constexpr int kDefaultCameraWidth = 960; // until a camera panel reports its size
    // After a settings change the next frame waits this long at most for the result that answers it, so
    // what is drawn matches the settings; work that takes longer shows when it is done.
    static constexpr std::chrono::milliseconds kRedoWait{250};
    // Each new frame moves the automatic depth range this fraction of the way to its own percentiles.
    static constexpr float kRangeFollowFraction = 0.2f;

    // States its demand at once: make the presenter before starting the instrument.
    Presenter(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings);

    // Once per frame: states the demand, takes the newest result (waiting up to `wait` for one from a frame
    // not shown yet), uploads it and renders what changed. `timeSeconds` is the time of the call (the
    // view's motion adds the wait to it). Returns whether a new frame's result arrived.
    bool update(double timeSeconds, std::chrono::milliseconds wait = std::chrono::milliseconds(0));
    // What update() drew is on screen now: drawn and shown (`redrawn`), or kept because the frame would have
    // drawn the picture the screen shows already. Counts the device frame it shows, the latency, and the
    // frames drawn and kept.
    void presented(bool redrawn = true);
    // Waits up to `timeout` for the engine's next new frame and keeps it for the next update(), so that a
    // benchmark can time that update (on the CPU and on the GPU) without the wait; false if none came.
    bool awaitFrame(std::chrono::milliseconds timeout);
    // A companion's presenter draws no cloud of its own (the main one fuses its points), and the engine
    // colours its points on the CPU for that.
    void setDrawsCloud(bool draws) { drawsCloud_ = draws; }
    // Another source's accumulation gathers this one's frames: the engine colours every sample for it.
    void setGathered(bool gathered) { gathered_ = gathered; }
    // The sources whose points the cloud fuses with this one's (none: the cloud is this source's alone).
    void setCompanions(Companions* companions) { companions_ = companions; }
    // Whether the cloud shows several sources fused in one world.
    bool fusing() const;
    // Another source: nothing shown or measured in the old one carries over.
    void forgetShown();

    // Writes cloud.png, depth.png, confidence.png (as rendered, the depth and confidence with every sample
    // of the map however small they are shown) and camera.png (the camera's image at its full resolution,
    // where the frame shown has one) into `directory`; returns the names of the files written.
    Expected<std::vector<std::string>> savePanels(const std::string& directory);
    // Writes the panels and the points drawn as cloud.ply (camera frame) into a directory under `parent`
    // named after the frame, new each time (frame-N, frame-N-2, …); returns that directory. Says where it
    // went, or why it failed, in the log (and so, in the window, on screen).
    Expected<std::string> saveSnapshot(const std::string& parent);
    // The fused cloud as last drawn, as a PLY in the world frame: every source's kept samples with their
    // own colours, source after source (the comments count each one's points).
    Status writeFusedPly(const std::string& path) const;

    Settings& settings() { return settings_; }
    const Settings& settings() const { return settings_; }
    engine::Instrument& instrument() { return instrument_; }
    const render::ViewRenderer& renderer() const { return renderer_; }
    void resizeCloud(int width, int height) { renderer_.resizeCloud(width, height); }
    // Tests on a loaded machine wait longer, so "the next frame shows it" does not depend on the load.
    void setRedoWait(std::chrono::milliseconds wait) { redoWait_ = wait; }
    // The sizes the panels are shown at, as the window last drew them (the engine makes no more than that).
    void setCameraShownWidth(int width) { cameraShownWidth_ = width; }
    void setDataPanelsShownWidth(int width) { dataPanelsShownWidth_ = width; }

    // The result drawn last (null before the first).
    const processing::ShownFramePtr& shown() const { return shown_; }
    // The demand stated last.
    const engine::Demand& demand() const { return demand_; }
    // The depth panel's range and colormap as last rendered (the automatic range follows each frame).
    const DepthLegend& depthLegend() const { return legend_; }
    // Points measured in the world, drawn into the cloud.
    Anchors& anchors() { return anchors_; }
    const Anchors& anchors() const { return anchors_; }
    // The matrix the last cloud was drawn with (depth camera frame to clip space).
    const glm::mat4& cloudViewProjection() const { return cloudViewProjection_; }
    // The cloud path the settings and the GL choose, and that with the reason ("CPU splat (software GL)").
    render::CloudPath cloudPath() const;
    std::string cloudPathText() const;
    // How long the last update() waited for the engine's result (benchmarks take it off the frame time).
    double lastWaitMs() const { return lastWaitMs_; }
    // Whether accumulate mode is on, the frame shown carries a pose, and the cloud is this source's alone.
    bool accumulating() const;
    std::uint64_t pointsShown();
    // Frames drawn per second (with or without a new device frame).
    double framesPerSecond() const { return frames_.perSecond(); }
    ViewerSummary summary();

private:
    engine::Demand demandOf() const;
    Expected<std::string> writeSnapshot(const std::string& parent);
    // With companions: the main panels, each companion's in source-N, and the fused cloud.ply.
    Expected<std::string> writeFusedSnapshot(const std::string& parent);
    void adopt(processing::ShownFramePtr shown);
    void renderCloud(double timeSeconds);
    // Fuses the companions' points with this source's and draws them, the world through this source's
    // camera.
    void renderFused(render::CloudParams params);
    // This source and its visible companions, each placed in the world.
    std::vector<FusedSource> fusedSources() const;
    void updateLegend();
    render::CloudParams cloudParams(double timeSeconds) const;
    // How the depth, confidence and overlay panels are drawn this frame.
    render::PanelParams panelParams() const;

    engine::Instrument& instrument_;
    render::ViewRenderer& renderer_;
    Settings settings_;
    engine::Demand demand_;
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
    base::RateMeter frames_;
    std::uint64_t framesKept_ = 0;
    bool drawsCloud_ = true;
    bool gathered_ = false;
    Companions* companions_ = nullptr;
};

} // namespace dc::ui
