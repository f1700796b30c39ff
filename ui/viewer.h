#pragma once

#include "devices/rate_meter.h"
#include "devices/session.h"
#include "processing/pipeline.h"
#include "processing/rolling_stats.h"
#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"
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
};

// The viewer's engine: one session, the processing pipeline, the frame's textures and a render target per
// panel. update() moves the newest frame through them; drawUi() shows the targets in ImGui panels. It owns
// GL objects, so it lives and dies on the GL thread with a context current.
class Viewer {
public:
    static constexpr int kDefaultCloudWidth = 960;
    static constexpr int kDefaultCloudHeight = 720;
    static constexpr int kDefaultCameraWidth = 960; // until a camera panel reports its size

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
    StatusLine statusLine() const;
    ViewerSummary summary() const;
    const std::string& sourceMessage() const { return sourceMessage_; }
    bool sourceRunning() const { return sourceRunning_; }
    const devices::FramePtr& currentFrame() const { return frame_; }
    const render::RenderTarget& cloudTarget() const { return cloudTarget_; }
    const render::RenderTarget& depthTarget() const { return depthTarget_; }
    const render::RenderTarget& confidenceTarget() const { return confidenceTarget_; }
    const render::RenderTarget& cameraTarget() const { return cameraTarget_; }

private:
    void drainEvents();
    void acceptFrame(devices::FramePtr frame);
    void renderPanels();
    void renderCloud(double timeSeconds);
    void countPoints();
    processing::Needs needs() const;
    processing::RollingStats& stage(const std::string& name) { return stages_[name]; }

    devices::Session session_;
    Settings settings_;
    processing::Pipeline pipeline_;
    render::FrameTextures textures_;
    render::PointCloudRenderer cloudRenderer_;
    render::PanelRenderer panelRenderer_;
    render::RenderTarget cloudTarget_;
    render::RenderTarget depthTarget_;
    render::RenderTarget confidenceTarget_;
    render::RenderTarget cameraTarget_;
    int cameraShownWidth_ = kDefaultCameraWidth;
    devices::FramePtr frame_;
    std::uint64_t framesShown_ = 0;
    std::uint64_t pointsDrawn_ = 0;
    std::uint64_t countedSequence_ = ~0ull;
    CloudSettings countedWith_;
    float pivotDepthMeters_ = 1.0f;
    std::string state_ = "closed";
    std::string sourceMessage_;
    bool sourceRunning_ = false;
    std::map<std::string, processing::RollingStats> stages_;
    devices::RateMeter updates_;
};

} // namespace dc::ui
