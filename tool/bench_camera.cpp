#include "tool/bench_camera.h"

#include "base/clock.h"
#include "base/files.h"
#include "base/log.h"
#include "devices/frame_list_device.h"
#include "render/gl_context.h"
#include "tool/bench_frames.h"
#include "tool/bench_gl_points.h"
#include "tool/bench_median.h"
#include "tool/options.h"
#include "ui/companions.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kWindowWidth = 1280;
constexpr int kWindowHeight = 720;
constexpr double kDisplayHz = 60.0;
constexpr double kWarmupSeconds = 1.0;
constexpr int kBareFrames = 60;

struct CameraCase {
    std::string name;
    devices::SyntheticConfig config;
    bool upsampling = false;
    bool pair = false;       // a second camera of the same kind beside it, fused in one cloud
    bool accumulate = false; // accumulate mode: every source's frames gathered into one world cloud
};

devices::SyntheticConfig cameraOf(int depthWidth, int depthHeight, int colourWidth, int colourHeight) {
    devices::SyntheticConfig c;
    c.depthWidth = depthWidth;
    c.depthHeight = depthHeight;
    c.cameraWidth = colourWidth;
    c.cameraHeight = colourHeight;
    return c;
}

// The sizes people stream: RealSense D4xx depth with a 1280x720 colour camera, the two-sensor rig, and the
// ARKit capture (256x192 LiDAR depth, 1920x1440 camera) with and without guided upsampling.
std::vector<CameraCase> cameraCases() {
    return {{"640x480 + colour 1280x720", cameraOf(640, 480, 1280, 720), false},
            {"848x480 + colour 1280x720", cameraOf(848, 480, 1280, 720), false},
            {"1280x720 + colour 1280x720", cameraOf(1280, 720, 1280, 720), false},
            {"rig 848x480 + colour 1280x720", devices::syntheticRigConfig(), false},
            {"ARKit 256x192 + camera 1920x1440", cameraOf(256, 192, 1920, 1440), false},
            {"ARKit 256x192 + camera 1920x1440, upsampled", cameraOf(256, 192, 1920, 1440), true},
            {"two 848x480 + colour 1280x720, fused", cameraOf(848, 480, 1280, 720), false, true},
            {"two 848x480 + colour 1280x720, fused, accumulating", cameraOf(848, 480, 1280, 720), false, true,
             true}};
}

// Eight distinct frames, made before anything is timed: the source then costs nothing. The camera sways,
// so each frame has an image of its own as a real camera's has (a still synthetic camera shares one image
// among its frames, and every stage that reads only the image would run once).
std::vector<frame::FramePtr> makeFrames(devices::SyntheticConfig config) {
    config.motion = true;
    return syntheticFrames(config, 8);
}

struct CaseResult {
    std::string name;
    double seconds = 0.0;
    std::uint64_t delivered = 0;
    std::uint64_t shown = 0; // the bench's own count: frames delivered in the window that reached the screen
    std::uint64_t shownByInstrument = 0; // the instrument's count over the same time (window edges differ)
    std::uint64_t inFlight = 0; // delivered in the window, neither shown nor dropped yet when it closed
    std::uint64_t droppedBeforeProcessing = 0; // replaced in the source's slot, or stale
    std::uint64_t droppedBeforeDisplay = 0;    // processed, then replaced before the GL thread took it
    std::vector<double> latencyMs;             // arrival (the source's stamp) to on screen (after glFinish)
    std::vector<double> glCpuMs;               // the GL thread's CPU per frame it drew
    std::vector<double> gpuClockMhz;           // the GPU's clock after each frame (none: not known)
    double processingCpuMs = 0.0;     // the processor thread's own CPU per new frame, median (not its pool's)
    double processingLatencyMs = 0.0; // arrival to result ready, median
    double processCpuMsPerFrame = 0.0; // every thread's CPU per delivered frame
    std::vector<engine::StageSummary> stages;
    std::uint64_t points = 0;
    std::string cloudPath;
    std::size_t samples = 0;
    int cloudWidth = 0, cloudHeight = 0;
    double bareGlPointsMs = 0.0;
    // The second camera of a pair over the same window: shown counted as the first camera's are (frames
    // delivered in the window that reached the screen), delivered and dropped by its own instrument.
    std::optional<engine::FrameCounts> second;
    // Accumulate mode: frames handed to the world cloud and replaced before it took them, over the window.
    std::optional<std::uint64_t> accumulationSkipped;
};

// The window's loop (tool/gui.cpp): wait for a new result until a display refresh after the last frame
// began, draw the UI, composite where the picture changed, and the frame is on screen once GL finishes.
class WindowLoop {
public:
    WindowLoop(ui::Viewer& viewer, ui::HeadlessUi& gui, const render::ViewRenderer& renderer)
        : viewer_(viewer), gui_(gui), renderer_(renderer) {}

    // One frame; what it drew, and each frame delivered since `firstSequence` that reached the screen, go
    // into `r` while `measuring`.
    void frame(CaseResult& r, bool measuring, std::uint64_t firstSequence = 0) {
        const auto now = Clock::now();
        const auto wait = std::max(std::chrono::ceil<std::chrono::milliseconds>(frameStart_ + period_ - now),
                                   std::chrono::milliseconds(0));
        const double cpuStart = base::threadCpuMs();
        viewer_.update(std::chrono::duration<double>(now - start_).count(), wait);
        frameStart_ = now + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double, std::milli>(viewer_.lastWaitMs()));
        gui_.newFrame(static_cast<float>(1.0 / kDisplayHz));
        viewer_.drawUi();
        const bool drawn = gui_.renderIfChanged(renderer_.contentVersion());
        glFinish(); // as a swap: the picture is on screen
        viewer_.presented(drawn);
        const auto& shown = viewer_.shown();
        const bool newOnScreen = shown && shown->frame->sequence != lastSequence_;
        if (newOnScreen)
            lastSequence_ = shown->frame->sequence;
        if (!measuring)
            return;
        if (drawn)
            r.glCpuMs.push_back(base::threadCpuMs() - cpuStart);
        if (newOnScreen && shown->frame->sequence >= firstSequence) {
            ++r.shown;
            r.latencyMs.push_back(static_cast<double>(base::monotonicNowNs() - shown->frame->timestampNs) *
                                  1e-6);
        }
        countSecond(r);
        if (const auto& clock = currentGpuClock())
            if (const auto mhz = clock->graphicsMhz())
                r.gpuClockMhz.push_back(*mhz);
    }

    // The pair's second camera numbers its frames from `firstSequence` in the window.
    void measureSecond(std::uint64_t firstSequence) { secondFirst_ = firstSequence; }

private:
    void countSecond(CaseResult& r) {
        if (viewer_.companions().empty() || !r.second)
            return;
        const auto& shown = viewer_.companions()[0].presenter().shown();
        if (!shown || shown->frame->sequence == secondLast_)
            return;
        secondLast_ = shown->frame->sequence;
        if (shown->frame->sequence >= secondFirst_)
            ++r.second->shown;
    }

    ui::Viewer& viewer_;
    ui::HeadlessUi& gui_;
    const render::ViewRenderer& renderer_;
    const Clock::time_point start_ = Clock::now();
    Clock::time_point frameStart_ = start_;
    const Clock::duration period_ =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kDisplayHz));
    std::uint64_t lastSequence_ = ~0ull;
    std::uint64_t secondFirst_ = 0;
    std::uint64_t secondLast_ = ~0ull;
};

// Frames delivered while measuring: the source numbers its frames from 0 in delivery order, so the
// window's frames are those numbered from the count delivered when it opened. Drops are counted over the
// same time; what is left was still on its way when the window closed.
void countFrames(CaseResult& r, const engine::FrameCounts& f0, const engine::FrameCounts& f1,
                 const engine::ProcessorCounts& p0, const engine::ProcessorCounts& p1) {
    r.delivered = f1.delivered - f0.delivered;
    r.shownByInstrument = f1.shown - f0.shown;
    r.droppedBeforeDisplay = p1.framesUnshown - p0.framesUnshown;
    r.droppedBeforeProcessing = (f1.dropped - f0.dropped) - r.droppedBeforeDisplay;
    const std::uint64_t accounted = r.shown + r.droppedBeforeDisplay + r.droppedBeforeProcessing;
    r.inFlight = r.delivered > accounted ? r.delivered - accounted : 0;
}

// The pair's second camera: the same kind of frames, four frames out of step with the first camera's, placed
// 20 cm to its right (what it sees does not line up with the first camera's scene; what it costs is a
// second camera's).
Status addSecondCamera(const CameraCase& c, const BenchCameraOptions& o, ui::Viewer& viewer) {
    auto frames = makeFrames(c.config);
    std::rotate(frames.begin(), frames.begin() + 4, frames.end());
    auto device = std::make_unique<devices::FrameListDevice>(std::move(frames), o.fps, c.name + ", second");
    frame::RigidTransform right;
    right.translationMeters = {0.2, 0.0, 0.0};
    device->place(right);
    auto companion = ui::Companion::create(std::move(device), c.name + ", second", viewer.settings());
    if (!companion)
        return companion.error();
    viewer.companions().add(std::move(*companion));
    return {};
}

engine::FrameCounts secondCounts(ui::Viewer& viewer) {
    return viewer.companions().empty() ? engine::FrameCounts{}
                                       : viewer.companions()[0].instrument().status().frames;
}

Expected<CaseResult> runCase(const CameraCase& c, const BenchCameraOptions& o) {
    auto frames = makeFrames(c.config);
    if (frames.size() < 8 || !frames.back())
        return Error{c.name + ": cannot make the synthetic frames"};
    ui::HeadlessUi gui;
    if (Status s = gui.init(kWindowWidth, kWindowHeight); !s)
        return s.error();
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return s.error();
    gui.setDrawsChangedFramesWhole(!renderer.softwareGl()); // as the window presents
    engine::Instrument instrument(
        std::make_unique<devices::FrameListDevice>(std::move(frames), o.fps, c.name), c.name);
    ui::Settings settings; // the default view and panels, as a new user meets them
    settings.processing.upsampling = c.upsampling;
    settings.accumulate.enabled = c.accumulate;
    ui::Viewer viewer(instrument, renderer, settings);
    if (c.pair)
        if (Status s = addSecondCamera(c, o, viewer); !s)
            return s.error();
    instrument.start();
    CaseResult r;
    r.name = c.name;
    WindowLoop loop(viewer, gui, renderer);
    const auto warm = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(kWarmupSeconds));
    while (Clock::now() < warm)
        loop.frame(r, false);
    const engine::FrameCounts f0 = instrument.status().frames;
    const engine::ProcessorCounts p0 = instrument.processor().counts();
    const engine::FrameCounts second0 = secondCounts(viewer);
    const std::uint64_t skipped0 = instrument.accumulation().skipped();
    if (c.pair) {
        r.second = engine::FrameCounts{};
        loop.measureSecond(second0.delivered);
    }
    const double cpu0 = base::processCpuMs();
    const auto start = Clock::now();
    const auto end =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
    while (Clock::now() < end)
        loop.frame(r, true, f0.delivered);
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    countFrames(r, f0, instrument.status().frames, p0, instrument.processor().counts());
    if (r.second) {
        const engine::FrameCounts second1 = secondCounts(viewer);
        r.second->delivered = second1.delivered - second0.delivered;
        r.second->dropped = second1.dropped - second0.dropped;
    }
    if (c.accumulate)
        r.accumulationSkipped = instrument.accumulation().skipped() - skipped0;
    r.processCpuMsPerFrame =
        (base::processCpuMs() - cpu0) / static_cast<double>(std::max<std::uint64_t>(r.delivered, 1));
    r.processingCpuMs = instrument.processor().cpuMs().median();
    r.processingLatencyMs = instrument.processor().latencyMs().median();
    r.stages = instrument.stages().all();
    r.points = viewer.summary().pointsDrawn;
    r.cloudPath = viewer.cloudPathText();
    if (const processing::ShownFramePtr& shown = viewer.shown(); shown && shown->depth.data) {
        r.samples = static_cast<std::size_t>(shown->depth.width()) * shown->depth.height();
        r.cloudWidth = renderer.cloudTarget().width();
        r.cloudHeight = renderer.cloudTarget().height();
        r.bareGlPointsMs = bareGlPoints(*shown, r.cloudWidth, r.cloudHeight, kBareFrames).wall;
    }
    return r;
}

double ratio(std::uint64_t part, std::uint64_t whole) {
    return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

void printResult(const CaseResult& r) {
    const Spread latency = spreadOf(r.latencyMs), gl = spreadOf(r.glCpuMs);
    std::printf("%s: %zu samples, %s, %llu points\n", r.name.c_str(), r.samples, r.cloudPath.c_str(),
                static_cast<unsigned long long>(r.points));
    std::printf(
        "  shown %llu of %llu delivered (%.3f) in %.1f s; dropped before processing %llu, before "
        "display %llu; in flight at the end %llu\n",
        static_cast<unsigned long long>(r.shown), static_cast<unsigned long long>(r.delivered),
        ratio(r.shown, r.delivered), r.seconds, static_cast<unsigned long long>(r.droppedBeforeProcessing),
        static_cast<unsigned long long>(r.droppedBeforeDisplay), static_cast<unsigned long long>(r.inFlight));
    std::printf(
        "  arrival -> screen median %.1f ms, p99 %.1f ms (arrival -> processed %.1f ms) | GL thread CPU "
        "per frame drawn median %.2f ms, p99 %.2f ms | processor thread's own CPU per frame %.2f ms | "
        "every thread's CPU per delivered frame %.1f ms\n",
        latency.median, latency.p99, r.processingLatencyMs, gl.median, gl.p99, r.processingCpuMs,
        r.processCpuMsPerFrame);
    if (r.second)
        std::printf("  second camera: shown %llu of %llu delivered (%.3f), dropped %llu\n",
                    static_cast<unsigned long long>(r.second->shown),
                    static_cast<unsigned long long>(r.second->delivered),
                    ratio(r.second->shown, r.second->delivered),
                    static_cast<unsigned long long>(r.second->dropped));
    if (r.accumulationSkipped)
        std::printf(
            "  accumulated: %llu points in the world cloud; %llu frames replaced before it took them\n",
            static_cast<unsigned long long>(r.points),
            static_cast<unsigned long long>(*r.accumulationSkipped));
    std::printf(
        "  bare GL_POINTS of every sample into the %dx%d cloud panel %.2f ms%s; stage medians:", r.cloudWidth,
        r.cloudHeight, r.bareGlPointsMs, gpuClockText(spreadOf(r.gpuClockMhz).median).c_str());
    for (const engine::StageSummary& s : r.stages)
        std::printf(" %s %.2f", s.name.c_str(), s.medianMs);
    std::printf("\n");
}

nlohmann::json toJson(const CaseResult& r) {
    const Spread latency = spreadOf(r.latencyMs), gl = spreadOf(r.glCpuMs);
    nlohmann::json stages = nlohmann::json::object();
    for (const engine::StageSummary& s : r.stages)
        stages[s.name] = s.medianMs;
    nlohmann::json j{
        {"case", r.name},
        {"seconds", r.seconds},
        {"delivered", r.delivered},
        {"shown", r.shown},
        {"shownByInstrument", r.shownByInstrument},
        {"inFlightAtEnd", r.inFlight},
        {"shownOverDelivered", ratio(r.shown, r.delivered)},
        {"droppedBeforeProcessing", r.droppedBeforeProcessing},
        {"droppedBeforeDisplay", r.droppedBeforeDisplay},
        {"latencyMs", {{"median", latency.median}, {"p99", latency.p99}, {"samples", r.latencyMs.size()}}},
        {"glThreadCpuMsPerFrameDrawn",
         {{"median", gl.median}, {"p99", gl.p99}, {"frames", r.glCpuMs.size()}}},
        {"processorThreadCpuMsPerFrame", r.processingCpuMs},
        {"processingLatencyMs", r.processingLatencyMs},
        {"processCpuMsPerDeliveredFrame", r.processCpuMsPerFrame},
        {"samples", r.samples},
        {"points", r.points},
        {"cloudPath", r.cloudPath},
        {"cloudPanel", {r.cloudWidth, r.cloudHeight}},
        {"bareGlPointsMs", r.bareGlPointsMs},
        {"gpuClockMhz", spreadOf(r.gpuClockMhz).median},
        {"stageMedianMs", stages}};
    if (r.second)
        j["secondCamera"] = {{"delivered", r.second->delivered},
                             {"shown", r.second->shown},
                             {"dropped", r.second->dropped},
                             {"shownOverDelivered", ratio(r.second->shown, r.second->delivered)}};
    if (r.accumulationSkipped)
        j["accumulationSkipped"] = *r.accumulationSkipped;
    return j;
}

} // namespace

CLI::App* addBenchCameraCommand(CLI::App& bench, BenchCameraOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "camera",
        "end to end at a camera's size and rate: frames shown vs delivered, latency to screen, CPU");
    cmd->add_option("--seconds", o.seconds, "measured seconds per case, after a second of warm-up")
        ->check(CLI::Range(0.5, 600.0))
        ->capture_default_str();
    cmd->add_option("--fps", o.fps, "the camera's frame rate")
        ->check(CLI::Range(1.0, 240.0))
        ->capture_default_str();
    std::vector<std::string> names;
    for (const CameraCase& c : cameraCases())
        names.push_back(c.name);
    cmd->add_option("--case", o.only, "run only this case")->check(CLI::IsMember(names));
    cmd->add_option("--json", o.jsonPath, "also write every figure as JSON to this file");
    return cmd;
}

int runBenchCamera(const BenchCameraOptions& o) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    std::printf(
        "bench camera on %s: frames at %.0f fps, a %dx%d window at %.0f Hz, default view and panels\n",
        context->rendererName().c_str(), o.fps, kWindowWidth, kWindowHeight, kDisplayHz);
    nlohmann::json results = nlohmann::json::array();
    for (const CameraCase& c : cameraCases()) {
        if (!o.only.empty() && c.name != o.only)
            continue;
        auto r = runCase(c, o);
        if (!r) {
            std::fprintf(stderr, "depthcloud: error: %s\n", r.error().message.c_str());
            return kExitFailure;
        }
        printResult(*r);
        results.push_back(toJson(*r));
    }
    if (o.jsonPath.empty())
        return kExitOk;
    const nlohmann::json j{{"renderer", context->rendererName()}, {"fps", o.fps}, {"cases", results}};
    if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
