#include "ui/viewer.h"

#include "base/clock.h"
#include "base/files.h"
#include "base/log.h"
#include "base/rolling_stats.h"
#include "devices/frame_pacer.h"
#include "devices/replay/replay_device.h"
#include "devices/source_spec.h"
#include "exporting/ply.h"
#include "frame/image_io.h"
#include "processing/aura.h"
#include "processing/confidence_filter.h"
#include "processing/fog.h"
#include "processing/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace dc::ui {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The orbit pivot: the median valid depth, so the swing turns the cloud about the middle of the scene.
float medianDepth(const frame::DepthData& depth) {
    std::vector<float> valid;
    const auto& pixels = depth.depthMeters.pixels;
    valid.reserve(pixels.size() / 4 + 1);
    for (std::size_t i = 0; i < pixels.size(); i += 4) // every 4th sample is plenty for a median
        if (std::isfinite(pixels[i]) && pixels[i] > 0.0f)
            valid.push_back(pixels[i]);
    if (valid.empty())
        return 1.0f;
    const auto mid = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2);
    std::nth_element(valid.begin(), mid, valid.end());
    return *mid;
}

// The camera panel is for looking, not measuring: its texture is rendered at the size it is shown (in
// steps, so resizing the panel does not reallocate every frame), never above the image's own size.
constexpr int kCameraWidthStep = 64;

int cameraPanelWidth(int imageWidth, int shownWidth) {
    const int stepped = (shownWidth + kCameraWidthStep - 1) / kCameraWidthStep * kCameraWidthStep;
    return std::clamp(stepped, 1, imageWidth);
}

// The automatic colormap range: the 2nd to 98th percentile of the valid depth, so a few outliers do not
// flatten the ramp; at least a centimetre wide.
std::optional<std::pair<float, float>> percentileRange(const frame::DepthData& depth) {
    std::vector<float> valid;
    const auto& pixels = depth.depthMeters.pixels;
    valid.reserve(pixels.size() / 2 + 1);
    for (std::size_t i = 0; i < pixels.size(); i += 2)
        if (std::isfinite(pixels[i]) && pixels[i] > 0.0f)
            valid.push_back(pixels[i]);
    if (valid.empty())
        return std::nullopt;
    const auto at = [&](double q) {
        const auto it =
            valid.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(valid.size() - 1));
        std::nth_element(valid.begin(), it, valid.end());
        return *it;
    };
    const float low = at(0.02);
    const float high = std::max(at(0.98), low + 0.01f);
    return std::make_pair(low, high);
}

// Resident memory from /proc, so the stats panel shows what the process really holds.
double residentMebibytes() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    if (!(statm >> pages >> resident))
        return 0.0;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

bool sameCounting(const CloudSettings& a, const CloudSettings& b) {
    return a.minConfidence == b.minConfidence && a.nearMeters == b.nearMeters;
}

render::OrbitView combine(const render::OrbitView& manual, const render::OrbitView& automatic) {
    return {manual.yawRadians + automatic.yawRadians, manual.pitchRadians + automatic.pitchRadians,
            manual.zoom * automatic.zoom, manual.panMeters + automatic.panMeters};
}

} // namespace

Viewer::Viewer(std::unique_ptr<devices::Device> device, Settings settings)
    : settings_(settings), pipeline_(processing::makeDefaultPipeline()) {
    sanitize(settings_);
    adoptDevice(*device);
    session_ = std::make_unique<devices::Session>(std::move(device));
}

// A replay hands the UI its timeline; every other source has none.
void Viewer::adoptDevice(devices::Device& device) {
    const auto* replay = dynamic_cast<const devices::replay::ReplayDevice*>(&device);
    replay_ = replay ? replay->control() : nullptr;
    awaitedSeek_ = 0;
}

Viewer::~Viewer() {
    exportJob_.reset();
    if (recording_)
        (void)stopRecording();
    session_->stop();
}

Status Viewer::init() {
    if (Status s = cloudRenderer_.init(); !s)
        return s;
    if (Status s = panelRenderer_.init(); !s)
        return s;
    if (Status s = accumulatedPoints_.init(); !s)
        return s;
    resizeCloud(kDefaultCloudWidth, kDefaultCloudHeight);
    // An instrument shows the sensor's own samples, not blends of neighbours; the cloud is drawn 1:1.
    cloudTarget_.setSampling(render::Sampling::Nearest);
    depthTarget_.setSampling(render::Sampling::Nearest);
    confidenceTarget_.setSampling(render::Sampling::Nearest);
    startSession();
    return {};
}

// A source that cannot start does not fail the viewer: the panels say why.
void Viewer::startSession() {
    sourceMessage_.clear();
    state_ = "closed";
    if (Status s = session_->start(); !s) {
        sourceMessage_ = s.error().message;
        sourceRunning_ = false;
        logError(session_->description() + ": " + sourceMessage_);
        return;
    }
    sourceRunning_ = true;
}

void Viewer::seekReplay(std::size_t index) {
    if (!replay_)
        return;
    awaitedSeek_ = replay_->seekToIndex(index);
    pipeline_.reset(); // temporal smoothing must not blend frames across the jump
}

void Viewer::stepReplay(int frames) {
    if (!replay_)
        return;
    awaitedSeek_ = replay_->step(frames);
    pipeline_.reset();
}

Status Viewer::startExport(exporting::ExportFormat format, const std::string& directory, std::size_t first,
                           std::size_t end) {
    if (!replay_)
        return Error{"export needs a replay source"};
    if (exportJob_ && !exportJob_->finished())
        return Error{"an export is already running"};
    exporting::ExportOptions options;
    options.format = format;
    options.outDirectory = directory;
    options.frames = {first, end};
    auto job = ExportJob::start(currentSpec_, options);
    if (!job) {
        logError("export: " + job.error().message);
        return job.error();
    }
    exportJob_ = std::move(*job);
    return {};
}

Status Viewer::startRecording(const std::string& path) {
    if (recording_)
        return Error{"already recording to " + recording_->path()};
    auto r = devices::recording::SessionRecording::start(*session_, path);
    if (!r) {
        logError("record: " + r.error().message);
        return r.error();
    }
    recording_ = std::move(*r);
    logInfo("recording to " + path);
    return {};
}

Status Viewer::stopRecording() {
    if (!recording_)
        return {};
    const devices::recording::RecorderStats stats = recording_->stats();
    Status s = recording_->stop();
    const std::string path = recording_->path();
    recording_.reset();
    if (!s) {
        logError("recording " + path + ": " + s.error().message);
        return s;
    }
    logInfo("recorded " + std::to_string(stats.framesWritten) + " frames (" +
            std::to_string(stats.framesDropped) + " dropped) to " + path);
    return {};
}

RecordView Viewer::recordView() const {
    if (!recording_)
        return {};
    const devices::recording::RecorderStats s = recording_->stats();
    return {true, s.framesWritten, s.framesDropped, s.bytesWritten};
}

Status Viewer::openSource(const std::string& spec) {
    auto device = devices::openSourceSpec(spec);
    if (!device) {
        sourcePanel_.error = device.error().message;
        logError(spec + ": " + device.error().message);
        return device.error();
    }
    sourcePanel_.error.clear();
    currentSpec_ = spec;
    rememberSource(settings_, spec);
    switchSource(std::move(*device));
    return {};
}

void Viewer::switchSource(std::unique_ptr<devices::Device> device) {
    if (recording_)
        (void)stopRecording();
    session_->stop();
    adoptDevice(*device);
    session_ = std::make_unique<devices::Session>(std::move(device));
    // Another source means another world: nothing measured in the old one carries over.
    pipeline_.reset();
    anchors_.clear();
    accumulation_.clear();
    frame_.reset();
    stages_.clear();
    latencyMs_ = base::RollingStats();
    startSession();
    logInfo("source: " + session_->description());
}

void Viewer::resizeCloud(int width, int height) {
    cloudTarget_.resize(std::max(width, 1), std::max(height, 1));
}

bool Viewer::update(double timeSeconds, std::chrono::milliseconds wait) {
    updates_.tick();
    drainEvents();
    std::optional<frame::FramePtr> next;
    if (sourceRunning_)
        next = wait.count() > 0 ? session_->waitForFrame(wait) : session_->takeLatest();
    // After a seek, frames decoded before it are still in flight: the first one shown is the one asked for.
    const bool stale = next && *next && (*next)->replay && (*next)->replay->seekGeneration < awaitedSeek_;
    if (next && *next && !stale)
        acceptFrame(std::move(*next));
    if (frame_ && !sameCounting(countedWith_, settings_.cloud))
        countPoints();
    if (frame_ && settings_.panels.cloud)
        renderCloud(timeSeconds);
    return next.has_value();
}

void Viewer::drainEvents() {
    for (const devices::SessionEvent& e : session_->drainEvents()) {
        state_ = devices::toString(e.state);
        if (e.kind == devices::SessionEvent::Kind::EndOfStream)
            state_ = "end of stream";
        if (!e.message.empty())
            sourceMessage_ = e.message;
    }
}

void Viewer::acceptFrame(frame::FramePtr frame) {
    auto start = Clock::now();
    frame = pipeline_.run(std::move(frame), settings_.processing, needs());
    stage("process").add(millisecondsSince(start));
    for (const processing::StageTiming& t : pipeline_.lastTimings())
        stage(t.name).add(t.milliseconds);
    const bool firstFrame = !frame_;
    frame_ = std::move(frame);
    ++framesShown_;
    if (firstFrame && shownDepth())
        pivotDepthMeters_ = medianDepth(*shownDepth());

    start = Clock::now();
    textures_.upload(*frame_, processing::showsSmoothed(*frame_, settings_.processing.depthSource));
    stage("upload").add(millisecondsSince(start));
    updateLegend();
    renderPanels();
    renderEffects(ImGui::GetCurrentContext() ? ImGui::GetTime() : 0.0);
    countPoints();
    accumulate();
    // Only sources stamping frames with the monotonic clock have a latency; a recording's clock has none.
    if (session_->capabilities().monotonicTimestamps) {
        const double latency = static_cast<double>(base::monotonicNowNs() - frame_->timestampNs) * 1e-6;
        if (latency >= 0.0)
            latencyMs_.add(latency);
    }
}

void Viewer::countPoints() {
    countedWith_ = settings_.cloud;
    pointsDrawn_ = shownDepth()
                       ? processing::countDrawablePoints(*shownDepth(), settings_.cloud.minConfidence,
                                                         settings_.cloud.nearMeters)
                       : 0;
}

void Viewer::renderPanels() {
    const auto start = Clock::now();
    const PanelVisibility& show = settings_.panels;
    if (show.depth && textures_.hasDepth()) {
        depthTarget_.resize(textures_.depthWidth(), textures_.depthHeight());
        panelRenderer_.renderDepth(depthTarget_, textures_, legend_.minMeters, legend_.maxMeters,
                                   legend_.colormap);
    }
    if (show.confidence && textures_.hasDepth()) {
        confidenceTarget_.resize(textures_.depthWidth(), textures_.depthHeight());
        panelRenderer_.renderConfidence(confidenceTarget_, textures_);
    }
    if (show.camera && textures_.cameraWidth() > 0) {
        const int w = cameraPanelWidth(textures_.cameraWidth(), cameraShownWidth_);
        const int h = std::max(1, textures_.cameraHeight() * w / textures_.cameraWidth());
        cameraTarget_.resize(w, h);
        panelRenderer_.renderCamera(cameraTarget_, textures_);
    }
    stage("panels").add(millisecondsSince(start));
}

void Viewer::renderCloud(double timeSeconds) {
    const auto start = Clock::now();
    render::CloudParams params;
    const render::OrbitView view =
        combine(settings_.cloud.orbit, render::autoOffset(settings_.cloud.motion, timeSeconds));
    const float aspect = static_cast<float>(cloudTarget_.width()) / static_cast<float>(cloudTarget_.height());
    params.viewProjection = render::cloudViewProjection(
        view, pivotDepthMeters_, render::verticalFovRadians(textures_.depthIntrinsics()), aspect);
    params.minConfidence = settings_.cloud.minConfidence;
    params.nearMeters = settings_.cloud.nearMeters;
    params.pointSizePixels = settings_.cloud.pointSizePixels;
    params.anchors = anchors_.inCameraFrame(frame_->pose);
    if (accumulating()) {
        // The worker may be adding right now: then the points uploaded last time are drawn again.
        accumulation_.tryRead(
            [this](processing::PointAccumulator& points) { accumulatedPoints_.sync(points); });
        params.accumulated = &accumulatedPoints_;
        params.worldToClip = params.viewProjection * glm::mat4(glm::inverse(toMatrix(*frame_->pose)));
    }
    cloudViewProjection_ = params.viewProjection;
    cloudRenderer_.render(cloudTarget_, textures_, params);
    stage("cloud").add(millisecondsSince(start));
}

std::uint64_t Viewer::pointsShown() const {
    return accumulating() ? accumulation_.size() : pointsDrawn_;
}

bool Viewer::accumulating() const {
    return settings_.accumulate.enabled && frame_ && frame_->pose;
}

void Viewer::accumulate() {
    if (!accumulating())
        return;
    const auto start = Clock::now();
    const AccumulateSettings& a = settings_.accumulate;
    accumulation_.submit({frame_, settings_.cloud.minConfidence, settings_.cloud.nearMeters,
                          static_cast<std::size_t>(a.budgetThousands) * 1000, a.voxelMillimeters * 1e-3f});
    stage("accumulate").add(millisecondsSince(start));
}

void Viewer::updateLegend() {
    const DepthRange& r = settings_.depthRange;
    legend_ = {r.minMeters, r.maxMeters, r.colormap, r.automatic};
    if (r.automatic && shownDepth()) {
        if (const auto range = percentileRange(*shownDepth())) {
            legend_.minMeters = range->first;
            legend_.maxMeters = range->second;
        }
    }
}

ProbeSource Viewer::probeSource() const {
    const frame::DepthData* depth = shownDepth();
    if (!depth)
        return {};
    return {depth, frame_->cameraIntrinsics.scaledTo(depth->depthMeters.width, depth->depthMeters.height)};
}

processing::Needs Viewer::needs() const {
    const PanelVisibility& show = settings_.panels;
    return {show.cloud, show.depth, show.confidence, show.camera, show.fog, show.aura};
}

const frame::DepthData* Viewer::shownDepth() const {
    return frame_ ? processing::shownDepth(*frame_, settings_.processing.depthSource) : nullptr;
}

// Fog and aura are made on the CPU for each new frame, only while their panels are shown.
void Viewer::renderEffects(double timeSeconds) {
    const PanelVisibility& show = settings_.panels;
    const processing::ProcessingSettings& p = settings_.processing;
    if (show.fog) {
        const auto start = Clock::now();
        const processing::RgbaImage fog = processing::renderFog(*frame_, p.fog, p.depthSource);
        fogTexture_.upload(fog.width, fog.height, fog.pixels.data());
        stage("fog").add(millisecondsSince(start));
    }
    if (show.aura) {
        const auto start = Clock::now();
        const processing::RgbaImage aura =
            processing::renderAura(*frame_, p.aura, p.depthSource, timeSeconds);
        auraTexture_.upload(aura.width, aura.height, aura.pixels.data());
        stage("aura").add(millisecondsSince(start));
    }
}

Status Viewer::savePanels(const std::string& directory) const {
    const std::pair<const char*, const render::RenderTarget*> panels[] = {
        {"cloud.png", &cloudTarget_},
        {"depth.png", &depthTarget_},
        {"confidence.png", &confidenceTarget_},
        {"camera.png", &cameraTarget_}};
    for (const auto& [name, target] : panels) {
        // A depth-only camera has no image to show: its camera panel is simply not written.
        if (target == &cameraTarget_ && target->width() == 0 && frame_ && frame_->capturedImage.empty())
            continue;
        if (target->width() == 0)
            return Error{std::string("cannot write ") + name + ": the panel has not been rendered"};
        if (Status s = target->savePng(directory + "/" + name); !s)
            return s;
    }
    return {};
}

Expected<std::string> Viewer::saveSnapshot(const std::string& parent) const {
    if (!frame_)
        return Error{"no frame to save yet"};
    const std::string dir = parent + "/frame-" + std::to_string(frame_->sequence);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        return Error{dir + ": cannot create directory: " + ec.message()};
    if (Status s = savePanels(dir); !s)
        return s.error();
    const auto points =
        processing::buildPointCloud(*frame_, settings_.cloud.minConfidence, settings_.cloud.nearMeters);
    const auto ply = exporting::encodePly(points, {"depthcloud snapshot of " + session_->description()});
    if (Status s = base::writeFileAtomically(dir + "/cloud.ply", ply); !s)
        return s.error();
    logInfo("snapshot: " + dir);
    return dir;
}

StatusLine Viewer::statusLine() const {
    const devices::SessionStats stats = session_->stats();
    StatusLine line{session_->description(),
                    state_,
                    sourceMessage_,
                    stats.deviceFps,
                    updates_.perSecond(),
                    stats.framesDropped,
                    pointsShown(),
                    {},
                    std::nullopt};
    for (const auto& [name, samples] : stages_)
        line.stageMedians.push_back({name, samples.median()});
    if (latencyMs_.count() > 0)
        line.latencyMs = latencyMs_.median();
    return line;
}

StatsView Viewer::statsView() const {
    const devices::SessionStats stats = session_->stats();
    StatsView v{stats.deviceFps,
                updates_.perSecond(),
                stats.framesDropped,
                pointsShown(),
                std::nullopt,
                residentMebibytes(),
                {}};
    if (latencyMs_.count() > 0)
        v.latencyMs = latencyMs_.median();
    for (const auto& [name, samples] : stages_) {
        StageHistory h{name, samples.median(), samples.max(), {}};
        for (const double ms : samples.inOrder())
            h.history.push_back(static_cast<float>(ms));
        v.stages.push_back(std::move(h));
    }
    return v;
}

ViewerSummary Viewer::summary() const {
    const StatusLine line = statusLine();
    ViewerSummary s{line.source,
                    framesShown_,
                    line.framesDropped,
                    line.deviceFps,
                    line.viewerFps,
                    line.pointsDrawn,
                    0,
                    0,
                    line.stageMedians,
                    line.latencyMs};
    if (const frame::DepthData* depth = shownDepth()) {
        s.depthWidth = depth->depthMeters.width;
        s.depthHeight = depth->depthMeters.height;
    }
    return s;
}

} // namespace dc::ui
