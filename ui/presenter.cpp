#include "ui/presenter.h"

#include "base/files.h"
#include "base/log.h"
#include "exporting/ply.h"
#include "exporting/snapshot.h"
#include "processing/depth_statistics.h"
#include "ui/companions.h"

#include <algorithm>
#include <cstdio>

namespace dc::ui {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

render::OrbitView combine(const render::OrbitView& manual, const render::OrbitView& automatic) {
    return {manual.yawRadians + automatic.yawRadians, manual.pitchRadians + automatic.pitchRadians,
            manual.zoom * automatic.zoom, manual.panMeters + automatic.panMeters};
}

engine::QualityDemand qualityDemand(const QualitySettings& s) {
    engine::QualityDemand q;
    q.roiPercent = s.roiPercent;
    q.roi = {s.roiX, s.roiY, s.roiWidth, s.roiHeight};
    if (s.roiPercent == 0) {
        for (std::size_t i = 0; i + 1 < s.polygon.size(); i += 2)
            q.polygon.push_back({s.polygon[i], s.polygon[i + 1]});
    }
    q.windowFrames = s.windowFrames;
    q.nearMeters = s.nearMeters;
    q.farMeters = s.farMeters;
    q.flyingThresholdMeters = s.flyingThresholdMm * 1e-3f;
    if (s.groundTruthMm > 0.0f)
        q.groundTruthMeters = static_cast<double>(s.groundTruthMm) * 1e-3;
    if (s.baselineMm > 0.0f)
        q.baselineMeters = static_cast<double>(s.baselineMm) * 1e-3;
    q.designSubpixelRms = s.designSubpixelRms;
    q.causeOverlay = s.causeOverlay;
    q.map = processing::kQualityMaps[static_cast<std::size_t>(s.map)];
    q.alignment = s.alignment;
    return q;
}

} // namespace

Presenter::Presenter(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings)
    : instrument_(instrument), renderer_(renderer), settings_(std::move(settings)) {
    sanitize(settings_);
    renderer_.resizeCloud(kDefaultCloudWidth, kDefaultCloudHeight);
    // Before the source starts, so that not even its first frame carries what nobody shows.
    demand_ = demandOf();
    instrument_.setDemand(demand_);
}

void Presenter::forgetShown() {
    anchors_.clear();
    shown_.reset();
    awaited_.reset(); // taken from the source before, so it is that source's
    pivotSet_ = false;
    followedRange_.reset();
}

// The demand, in data terms, of what the panels show now.
engine::Demand Presenter::demandOf() const {
    const PanelVisibility& show = settings_.panels;
    const CloudSettings& cloud = settings_.cloud;
    engine::Demand d;
    d.cloud = show.cloud;
    d.pointColours = cloud.coloring == render::PointColoring::Camera;
    d.gpuCameraColours = drawsCloud_ && cloudPath() == render::CloudPath::Points;
    d.depthImage = show.depth || (show.camera && settings_.camera.depthOverlay);
    d.confidencePanel = show.confidence;
    d.cameraPanelWidth = show.camera ? cameraShownWidth_ : 0;
    d.dataPanelWidth = d.depthImage || d.confidencePanel ? dataPanelsShownWidth_ : 0;
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
    d.gathered = gathered_;
    d.accumulateBudget = static_cast<std::size_t>(a.budgetThousands) * 1000;
    d.accumulateVoxelMeters = a.voxelMillimeters * 1e-3f;
    if (show.quality)
        d.quality = qualityDemand(settings_.quality);
    // Confidence colours read confidence like the confidence panel does.
    d.confidencePanel |= show.cloud && cloud.coloring == render::PointColoring::Confidence;
    return d;
}

bool Presenter::update(double timeSeconds, std::chrono::milliseconds wait) {
    const engine::Demand demand = demandOf();
    const bool changed = !(demand == demand_);
    demand_ = demand;
    instrument_.setDemand(demand);
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
    if (accumulating() && companions_)
        companions_->gather(instrument_.accumulation(), settings_);
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
    if (shown_ && show.cloud && drawsCloud_)
        renderCloud(timeSeconds);
    if (renderer_.contentVersion() != version)
        instrument_.recordStage("cloud", millisecondsSince(start));
    return fresh;
}

render::PanelParams Presenter::panelParams() const {
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

bool Presenter::awaitFrame(std::chrono::milliseconds timeout) {
    awaited_ = instrument_.waitForResult(timeout, true);
    return awaited_.has_value();
}

void Presenter::adopt(processing::ShownFramePtr shown) {
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

void Presenter::presented(bool redrawn) {
    if (shown_ && !presentedShown_)
        instrument_.presented(*shown_);
    presentedShown_ = true;
    if (redrawn)
        frames_.tick();
    else
        ++framesKept_;
}

render::CloudParams Presenter::cloudParams(double timeSeconds) const {
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

render::CloudPath Presenter::cloudPath() const {
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

std::string Presenter::cloudPathText() const {
    const render::CloudPath path = cloudPath();
    std::string why = settings_.cloud.path != CloudPathChoice::Automatic ? "chosen"
                      : path == render::CloudPath::Splat                 ? "software GL"
                                                                         : "hardware GL";
    return std::string(render::toString(path)) + " (" + why + ")";
}

void Presenter::renderCloud(double timeSeconds) {
    renderer_.setCloudPath(cloudPath());
    const render::CloudParams params = cloudParams(timeSeconds);
    if (accumulating())
        renderer_.syncAccumulated(instrument_.accumulation());
    cloudViewProjection_ = params.viewProjection;
    // Accumulated, every source's points are in the world cloud already (Companions::gather).
    if (fusing() && !accumulating())
        renderFused(params);
    else
        renderer_.renderCloud(params, accumulating());
}

bool Presenter::fusing() const {
    return companions_ && !companions_->empty();
}

std::vector<FusedSource> Presenter::fusedSources() const {
    std::vector<FusedSource> sources{
        {shown_, placeInWorld(*shown_->frame, {}), instrument_.spec(), std::nullopt}};
    for (FusedSource& s : companions_->fusedSources())
        sources.push_back(std::move(s));
    return sources;
}

// Each visible companion's samples become a layer of this cloud, placed through the world into this
// source's camera frame: the GPU draws them from their own textures and the CPU splat projects them, with
// no work per point to place them first.
void Presenter::renderFused(render::CloudParams params) {
    const glm::dmat4 worldToMain =
        glm::inverse(toMatrix(frame::poseFromRigid(placeInWorld(*shown_->frame, {}))));
    const bool gpu = renderer_.cloudPath() == render::CloudPath::Points;
    for (std::size_t i = 0; i < companions_->size(); ++i) {
        Companion& c = (*companions_)[i];
        const processing::ShownFramePtr& shown = c.presenter().shown();
        if (!c.look.visible || !shown ||
            !companions_->paired(i, instrument_, shown_, settings_.sources.pairingToleranceMs))
            continue;
        const glm::dmat4 toWorld =
            toMatrix(frame::poseFromRigid(placeInWorld(*shown->frame, c.look.correction)));
        render::ViewRenderer& own = c.renderer();
        const processing::ShownCloud& cloud = own.cloud();
        params.layers.push_back(
            {gpu ? &own.cloudTextures() : nullptr, params.viewProjection * glm::mat4(worldToMain * toWorld),
             c.look.tinted ? glm::vec4(c.look.tint[0], c.look.tint[1], c.look.tint[2], 1.0f)
                           : glm::vec4(0.0f),
             cloud.depth.data, cloud.depth.intrinsics, cloud.colours,
             c.own.followsMain ? std::nullopt : std::optional(c.own.minConfidence)});
    }
    renderer_.renderCloud(params, false);
}

std::uint64_t Presenter::pointsShown() {
    if (accumulating())
        return instrument_.accumulation().size();
    if (fusing() && shown_) {
        std::uint64_t points = 0;
        for (const FusedSource& source : fusedSources())
            points += source.shown->pointCount;
        return points;
    }
    return shown_ ? shown_->pointCount : 0;
}

bool Presenter::accumulating() const {
    return settings_.accumulate.enabled && shown_ && shown_->frame->pose;
}

void Presenter::updateLegend() {
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

Expected<std::vector<std::string>> Presenter::savePanels(const std::string& directory) {
    auto pictures = renderer_.panelPictures(drawsCloud_);
    if (!pictures)
        return pictures.error();
    return exporting::writePanels(directory, *pictures, shown_ ? shown_->frame.get() : nullptr);
}

Expected<std::string> Presenter::saveSnapshot(const std::string& parent) {
    auto dir = writeSnapshot(parent);
    if (dir)
        logNotice("snapshot saved to " + *dir);
    else
        logError("snapshot not saved: " + dir.error().message);
    return dir;
}

Expected<std::string> Presenter::writeFusedSnapshot(const std::string& parent) {
    auto pictures = renderer_.panelPictures();
    if (!pictures)
        return pictures.error();
    auto dir = base::createFreshDirectory(parent, "frame-" + std::to_string(shown_->frame->sequence));
    if (!dir)
        return dir.error();
    if (auto written = exporting::writePanels(*dir, *pictures, shown_->frame.get()); !written)
        return written.error();
    if (auto written = companions_->savePanels(*dir); !written)
        return written.error();
    if (Status s = writeFusedPly(*dir + "/cloud.ply"); !s)
        return s.error();
    return dir;
}

Status Presenter::writeFusedPly(const std::string& path) const {
    if (!shown_ || !fusing())
        return Error{"no fused cloud drawn yet"};
    const CloudSettings& cloud = settings_.cloud;
    std::vector<processing::CloudPoint> points;
    std::vector<std::string> comments{
        "depthcloud: several sources fused in the world frame, source after source"};
    for (const FusedSource& source : fusedSources()) {
        auto own = worldCloud(source, source.minConfidence.value_or(cloud.minConfidence), cloud.nearMeters);
        comments.push_back(std::to_string(own.size()) + " points of " + source.name);
        points.insert(points.end(), own.begin(), own.end());
    }
    return base::writeFileAtomically(path, exporting::encodePly(points, comments));
}

Expected<std::string> Presenter::writeSnapshot(const std::string& parent) {
    if (!shown_)
        return Error{"no frame to save yet"};
    if (fusing())
        return writeFusedSnapshot(parent);
    auto pictures = renderer_.panelPictures();
    if (!pictures)
        return pictures.error();
    const exporting::SnapshotCloud cloud{settings_.cloud.minConfidence, settings_.cloud.nearMeters,
                                         settings_.cloud.coloring == render::PointColoring::Camera};
    return exporting::writeSnapshot(parent, *pictures, *shown_, cloud, instrument_.status().source);
}

ViewerSummary Presenter::summary() {
    const engine::InstrumentStatus s = instrument_.status();
    ViewerSummary summary{s.source,
                          s.frames,
                          frames_.perSecond(),
                          frames_.count(),
                          framesKept_,
                          pointsShown(),
                          cloudPathText(),
                          0,
                          0,
                          instrument_.stages().all(),
                          s.latencyMs,
                          std::nullopt,
                          std::nullopt};
    if (shown_) {
        summary.depthWidth = shown_->depth.width();
        summary.depthHeight = shown_->depth.height();
    }
    return summary;
}

} // namespace dc::ui
