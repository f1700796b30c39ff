#include "ui/viewer.h"

#include "base/log.h"
#include "devices/device.h"
#include "exporting/snapshot.h"
#include "frame/camera_model.h"
#include "processing/depth_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace dc::ui {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Resident memory from /proc, so the stats panel shows what the process really holds.
double residentMebibytes() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    if (!(statm >> pages >> resident))
        return 0.0;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

render::OrbitView combine(const render::OrbitView& manual, const render::OrbitView& automatic) {
    return {manual.yawRadians + automatic.yawRadians, manual.pitchRadians + automatic.pitchRadians,
            manual.zoom * automatic.zoom, manual.panMeters + automatic.panMeters};
}

engine::QualityDemand qualityDemand(const QualitySettings& s) {
    engine::QualityDemand q;
    q.roiPercent = s.roiPercent;
    q.roi = {s.roiX, s.roiY, s.roiWidth, s.roiHeight};
    q.windowFrames = s.windowFrames;
    q.nearMeters = s.nearMeters;
    q.farMeters = s.farMeters;
    q.flyingThresholdMeters = s.flyingThresholdMm * 1e-3f;
    if (s.groundTruthMm > 0.0f)
        q.groundTruthMeters = static_cast<double>(s.groundTruthMm) * 1e-3;
    return q;
}

} // namespace

Viewer::Viewer(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings)
    : instrument_(instrument), renderer_(renderer), settings_(std::move(settings)) {
    sanitize(settings_);
    // Panels are opaque: a panel over the cloud (stats, log, fog, aura, infrared) must not let the points
    // behind it show through and read as part of its picture.
    if (ImGui::GetCurrentContext())
        ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;
    renderer_.resizeCloud(kDefaultCloudWidth, kDefaultCloudHeight);
    // Before the source starts, so that not even its first frame carries what nobody shows.
    demand_ = demandOf();
    demandGeneration_ = instrument_.setDemand(demand_);
}

// The demand, in data terms, of what the panels show now.
engine::Demand Viewer::demandOf() const {
    const PanelVisibility& show = settings_.panels;
    const CloudSettings& cloud = settings_.cloud;
    engine::Demand d;
    d.cloud = show.cloud;
    d.pointColors = cloud.coloring == render::PointColoring::Camera;
    d.gpuCameraColours = cloudPath() == render::CloudPath::Points;
    d.depthImage = show.depth || (show.camera && settings_.camera.depthOverlay);
    d.confidencePanel = show.confidence;
    d.cameraPanelWidth = show.camera ? cameraShownWidth_ : 0;
    d.depthOverCamera = show.camera && settings_.camera.depthOverlay;
    d.colourOverDepth = show.depth && settings_.depthView.colourOverlay;
    d.infraredPanel = show.infrared;
    d.fog = show.fog;
    d.aura = show.aura;
    d.automaticRange = settings_.depthRange.automatic &&
                       (d.depthImage || (show.cloud && cloud.coloring == render::PointColoring::Depth));
    d.minConfidence = cloud.minConfidence;
    d.nearMeters = cloud.nearMeters;
    d.cloudDecimation = cloud.decimation;
    const render::RenderTarget& target = renderer_.cloudTarget();
    d.cloudPanelPixels = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height());
    d.processing = settings_.processing;
    const AccumulateSettings& a = settings_.accumulate;
    d.accumulate = a.enabled;
    d.accumulateBudget = static_cast<std::size_t>(a.budgetThousands) * 1000;
    d.accumulateVoxelMeters = a.voxelMillimeters * 1e-3f;
    if (show.quality)
        d.quality = qualityDemand(settings_.quality);
    // Confidence colours read confidence like the confidence panel does.
    d.confidencePanel |= show.cloud && cloud.coloring == render::PointColoring::Confidence;
    return d;
}

bool Viewer::update(double timeSeconds, std::chrono::milliseconds wait) {
    const engine::Demand demand = demandOf();
    const bool changed = !(demand == demand_);
    demand_ = demand;
    demandGeneration_ = instrument_.setDemand(demand);
    std::optional<processing::ShownFramePtr> next = std::exchange(awaited_, std::nullopt);
    const auto waitStart = Clock::now();
    if (!next && wait.count() > 0)
        next = instrument_.waitForResult(wait, true);
    else if (!next && changed && shown_)
        next = instrument_.waitForResult(redoWait_, false);
    lastWaitMs_ = millisecondsSince(waitStart);
    timeSeconds += lastWaitMs_ * 1e-3; // the view moves on to when the frame is drawn, not when it waited
    if (!next)
        next = instrument_.update();
    const bool fresh = next && (*next)->newFrame;
    if (next)
        adopt(std::move(*next));
    updateLegend();
    auto start = Clock::now();
    std::uint64_t version = renderer_.contentVersion();
    const PanelVisibility& show = settings_.panels;
    renderer_.renderPanels(panelParams());
    if (show.camera)
        renderer_.renderCameraImage(cameraShownWidth_);
    // A stage's time is what its work costs: a frame where it had nothing to redraw is not a sample.
    if (renderer_.contentVersion() != version)
        instrument_.recordStage("panels", millisecondsSince(start));
    start = Clock::now();
    version = renderer_.contentVersion();
    if (shown_ && show.cloud)
        renderCloud(timeSeconds);
    if (renderer_.contentVersion() != version)
        instrument_.recordStage("cloud", millisecondsSince(start));
    return fresh;
}

render::PanelParams Viewer::panelParams() const {
    const PanelVisibility& show = settings_.panels;
    // A two-sensor frame's depth over the camera is drawn aligned to the colour image; a single camera's
    // is the depth panel's image, drawn for it even while the depth panel is hidden.
    const bool depthOverCamera = show.camera && settings_.camera.depthOverlay;
    render::PanelParams panels;
    // The engine leaves the overlays to the GL path where it leaves it the camera colours (demandOf).
    panels.gpuOverlays = demand_.gpuCameraColours;
    const bool aligned = shown_ && renderer_.alignsDepthOverCamera(panels.gpuOverlays);
    panels.depth = show.depth || (depthOverCamera && !aligned);
    panels.confidence = show.confidence;
    panels.depthOverCamera = depthOverCamera;
    panels.colourOverDepth = show.depth && settings_.depthView.colourOverlay;
    panels.cameraShownWidth = cameraShownWidth_;
    panels.minMeters = legend_.minMeters;
    panels.maxMeters = legend_.maxMeters;
    panels.colormap = legend_.colormap;
    panels.shownWidth = dataPanelsShownWidth_;
    return panels;
}

bool Viewer::awaitFrame(std::chrono::milliseconds timeout) {
    awaited_ = instrument_.waitForResult(timeout, true);
    return awaited_.has_value();
}

void Viewer::adopt(processing::ShownFramePtr shown) {
    const auto start = Clock::now();
    shown_ = std::move(shown);
    presentedShown_ = false;
    renderer_.sync(*shown_);
    instrument_.recordStage("upload", millisecondsSince(start));
    if (!pivotSet_ && shown_->depth.data) {
        pivotDepthMeters_ = processing::medianDepth(shown_->depth.data->depthMeters);
        pivotSet_ = true;
        const frame::Intrinsics& k = shown_->depth.intrinsics;
        char line[160];
        std::snprintf(line, sizeof line, "calibration: depth %dx%d, fx %.1f fy %.1f, cx %.1f cy %.1f",
                      shown_->depth.width(), shown_->depth.height(), k.fx, k.fy, k.cx, k.cy);
        logInfo(line);
    }
}

void Viewer::presented(bool redrawn) {
    if (shown_ && !presentedShown_)
        instrument_.presented(*shown_);
    presentedShown_ = true;
    if (redrawn)
        uiFrames_.tick();
    else
        ++uiFramesKept_;
}

render::CloudParams Viewer::cloudParams(double timeSeconds) const {
    render::CloudParams params;
    const CloudSettings& cloud = settings_.cloud;
    const render::OrbitView view = combine(cloud.orbit, render::autoOffset(cloud.motion, timeSeconds));
    const render::RenderTarget& target = renderer_.cloudTarget();
    const float aspect =
        static_cast<float>(target.width()) / static_cast<float>(std::max(target.height(), 1));
    params.viewProjection = render::cloudViewProjection(
        view, pivotDepthMeters_, render::verticalFovRadians(shown_->depth.intrinsics), aspect);
    params.minConfidence = cloud.minConfidence;
    params.nearMeters = cloud.nearMeters;
    params.pointSizePixels = cloud.pointSizePixels;
    params.fillGaps = cloud.fillGaps;
    params.coloring = cloud.coloring;
    params.colormap = legend_.colormap;
    params.rangeMinMeters = legend_.minMeters;
    params.rangeMaxMeters = legend_.maxMeters;
    params.anchors = anchors_.inCameraFrame(shown_->frame->pose);
    if (accumulating())
        params.worldToClip = params.viewProjection * glm::mat4(glm::inverse(toMatrix(*shown_->frame->pose)));
    return params;
}

render::CloudPath Viewer::cloudPath() const {
    switch (settings_.cloud.path) {
    case CloudPathChoice::Points:
        return render::CloudPath::Points;
    case CloudPathChoice::Splat:
        return render::CloudPath::Splat;
    case CloudPathChoice::Automatic:
        break;
    }
    return renderer_.softwareGl() ? render::CloudPath::Splat : render::CloudPath::Points;
}

std::string Viewer::cloudPathText() const {
    const render::CloudPath path = cloudPath();
    std::string why = settings_.cloud.path != CloudPathChoice::Automatic ? "chosen"
                      : path == render::CloudPath::Splat                 ? "software GL"
                                                                         : "hardware GL";
    return std::string(render::toString(path)) + " (" + why + ")";
}

void Viewer::renderCloud(double timeSeconds) {
    renderer_.setCloudPath(cloudPath());
    const render::CloudParams params = cloudParams(timeSeconds);
    if (accumulating())
        renderer_.syncAccumulated(instrument_.accumulation());
    cloudViewProjection_ = params.viewProjection;
    renderer_.renderCloud(params, accumulating());
}

std::uint64_t Viewer::pointsShown() {
    if (accumulating())
        return instrument_.accumulation().size();
    return shown_ ? shown_->pointCount : 0;
}

bool Viewer::accumulating() const {
    return settings_.accumulate.enabled && shown_ && shown_->frame->pose;
}

void Viewer::updateLegend() {
    const DepthRange& r = settings_.depthRange;
    legend_ = {r.minMeters, r.maxMeters, r.colormap, r.automatic};
    if (!r.automatic || !shown_ || !shown_->automaticRange)
        return;
    // Once per device frame: a redo of the same frame (a setting changed) must not move the range again.
    if (!followedRange_ || shown_->frame->sequence != followedSequence_) {
        followedRange_ =
            processing::followRange(followedRange_, *shown_->automaticRange, kRangeFollowFraction);
        followedSequence_ = shown_->frame->sequence;
    }
    legend_.minMeters = followedRange_->minMeters;
    legend_.maxMeters = followedRange_->maxMeters;
}

ProbeSource Viewer::probeSource() const {
    if (!shown_ || !shown_->depth.data)
        return {};
    const auto& infrared = shown_->frame->infrared;
    return {shown_->depth.data.get(), shown_->depth.intrinsics, shown_->pointSeen.get(), shown_->frame.get(),
            infrared ? &*infrared : nullptr};
}

Status Viewer::openSource(const std::string& spec) {
    if (Status s = instrument_.openSource(spec); !s) {
        sourcePanel_.error = s.error().message;
        return s;
    }
    sourcePanel_.error.clear();
    rememberSource(settings_, spec);
    // Another source means another world: nothing measured in the old one carries over.
    anchors_.clear();
    shown_.reset();
    pivotSet_ = false;
    followedRange_.reset();
    measured_.reset();
    return {};
}

Status Viewer::openPath(const std::string& path) {
    Expected<std::string> spec = sourceSpecForPath(path);
    if (!spec) {
        sourcePanel_.error = spec.error().message;
        logWarning(spec.error().message);
        return spec.error();
    }
    return openSource(*spec);
}

Expected<std::vector<std::string>> Viewer::savePanels(const std::string& directory) {
    auto pictures = renderer_.panelPictures();
    if (!pictures)
        return pictures.error();
    return exporting::writePanels(directory, *pictures, shown_ ? shown_->frame.get() : nullptr);
}

Expected<std::string> Viewer::saveSnapshot(const std::string& parent) {
    auto dir = writeSnapshot(parent);
    if (dir)
        logNotice("snapshot saved to " + *dir);
    else
        logError("snapshot not saved: " + dir.error().message);
    return dir;
}

Expected<std::string> Viewer::writeSnapshot(const std::string& parent) {
    if (!shown_)
        return Error{"no frame to save yet"};
    auto pictures = renderer_.panelPictures();
    if (!pictures)
        return pictures.error();
    const exporting::SnapshotCloud cloud{settings_.cloud.minConfidence, settings_.cloud.nearMeters,
                                         settings_.cloud.coloring == render::PointColoring::Camera};
    return exporting::writeSnapshot(parent, *pictures, *shown_, cloud, instrument_.status().source);
}

namespace {

// "REC 1:05 | 1950 frames | 212.4 MB": how long, how much, how large so far.
std::string recordingText(const engine::RecordingStatus& r) {
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - r.started).count();
    char text[128];
    std::snprintf(text, sizeof text, "REC %lld:%02lld | %llu frames | %.1f MB",
                  static_cast<long long>(seconds / 60), static_cast<long long>(seconds % 60),
                  static_cast<unsigned long long>(r.frames), static_cast<double>(r.bytesWritten) / 1e6);
    return text;
}

} // namespace

StatusLine Viewer::statusLine() {
    const engine::InstrumentStatus s = instrument_.status();
    StatusLine line{
        s.source, s.state.text(), s.message, s.frames, uiFrames_.perSecond(), pointsShown(), cloudPathText(),
        {},       s.latencyMs,    {},        {}};
    for (const engine::StageSummary& stage : s.stages)
        line.stageMedians.push_back({stage.name, stage.medianMs});
    if (const engine::RecordingStatus r = instrument_.recording(); r.recording)
        line.recording = recordingText(r);
    if (shown_ && shown_->frame && shown_->frame->rig)
        line.calibration = frame::describe(*shown_->frame->rig);
    else if (s.unregisteredColour && shown_ && shown_->frame && !shown_->frame->capturedImage.empty())
        line.calibration = devices::kUnregisteredColourMessage;
    return line;
}

void Viewer::measure() {
    const auto now = Clock::now();
    const std::uint64_t version = renderer_.contentVersion();
    // A source that stops delivering (paused, ended, stalled) changes nothing on screen, but its rates fall
    // to zero within the rate window: they are taken again until they have, so no figure looks live.
    const bool ratesMoving =
        measured_ && (measured_->frames.deliveredPerSecond > 0.0 || measured_->frames.shownPerSecond > 0.0);
    if (measured_ && ((version == measuredVersion_ && !ratesMoving) || now - measuredAt_ < kMeasureInterval))
        return;
    measured_ = statsView();
    measuredVersion_ = version;
    measuredAt_ = now;
}

// The status line with the figures measure() took last; what the source is and does is always current.
StatusLine Viewer::shownStatusLine() {
    StatusLine line = statusLine();
    line.frames = measured_->frames;
    line.uiFps = measured_->uiFps;
    line.latencyMs = measured_->latencyMs;
    line.stageMedians.clear();
    for (const StageHistory& stage : measured_->stages)
        line.stageMedians.push_back({stage.name, stage.medianMs});
    return line;
}

StatsView Viewer::statsView() {
    const engine::InstrumentStatus s = instrument_.status();
    StatsView v{s.frames, uiFrames_.perSecond(), pointsShown(), s.latencyMs, residentMebibytes(), {}};
    for (const engine::StageSummary& stage : s.stages) {
        StageHistory h{stage.name, stage.medianMs, stage.maxMs, {}};
        for (const double ms : stage.history)
            h.history.push_back(static_cast<float>(ms));
        v.stages.push_back(std::move(h));
    }
    return v;
}

ViewerSummary Viewer::summary() {
    const engine::InstrumentStatus s = instrument_.status();
    ViewerSummary summary{s.source,
                          s.frames,
                          uiFrames_.perSecond(),
                          uiFrames_.count(),
                          uiFramesKept_,
                          pointsShown(),
                          cloudPathText(),
                          0,
                          0,
                          instrument_.stages().all(),
                          s.latencyMs};
    if (shown_) {
        summary.depthWidth = shown_->depth.width();
        summary.depthHeight = shown_->depth.height();
    }
    return summary;
}

} // namespace dc::ui
