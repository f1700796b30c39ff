#include "base/files.h"
#include "base/log.h"
#include "base/rolling_stats.h"
#include "devices/frame_list_device.h"
#include "devices/synthetic/synthetic_device.h"
#include "render/gl_context.h"
#include "render/gl_objects.h"
#include "render/orbit_camera.h"
#include "tool/bench_frames.h"
#include "tool/bench_gl_points.h"
#include "tool/bench_median.h"
#include "tool/gpu_clock.h"
#include "tool/options.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kRenderWarmupFrames = 20;
constexpr auto kRenderWarmup = std::chrono::milliseconds(1500);

struct BenchCase {
    const char* name;
    int depthWidth;
    int depthHeight;
    bool upsampling; // guided upsampling on: the ARKit-sized frame's showcase
};

// One path's full viewer frames: every panel shown, a new device frame and a turning view each frame,
// composited as the window composites: on software GL where the picture changed (ui::FrameDamage), on
// hardware GL whole, since a swap shows the whole back buffer.
struct PathResult {
    render::CloudPath path = render::CloudPath::Points;
    std::string variant;            // empty: the default view; else what the --breakdown run left out
    double medianMs = 0, p90Ms = 0; // wall, to glFinish
    double cpuMs = 0, gpuMs = 0;    // the GL thread's CPU submitting a frame, the GPU's time for it
    double gpuClockMhz = 0;         // the GPU's clock over those frames (0: not known)
    std::uint64_t points = 0;
    int decimation = 1;
    std::vector<engine::StageSummary> stages;
};

struct CaseResult {
    BenchCase c{};
    std::vector<PathResult> paths;
    double stillMs = 0;  // a frame of the same still view as the window runs it: kept, not drawn
    int stillDrawn = 0;  // of those timed, drawn all the same (0 when the check keeps every one)
    GlFrameMs floor;     // an ImGui frame compositing the panels, nothing new drawn
    GlFrameMs bare;      // GL_POINTS of every shown sample into the cloud panel's size, nothing else
    GlFrameMs barePaced; // the same, one draw per frame of the source's rate (bareGlPoints says why)
    std::size_t shownSamples = 0;
    int cloudWidth = 0, cloudHeight = 0;
};

double percentile(const base::RollingStats& stats, double fraction) {
    std::vector<double> sorted = stats.inOrder();
    if (sorted.empty())
        return 0.0;
    std::sort(sorted.begin(), sorted.end());
    return sorted[static_cast<std::size_t>(fraction * static_cast<double>(sorted.size() - 1))];
}

// Eight distinct noisy frames, made before timing starts so the capture thread costs nothing while the
// viewer is measured. They arrive at the camera's rate (--source-fps): each timed frame waits for the next
// one, and the wait is not counted.
std::vector<frame::FramePtr> makeFrames(const BenchCase& c) {
    devices::SyntheticConfig config;
    config.depthWidth = c.depthWidth;
    config.depthHeight = c.depthHeight;
    return syntheticFrames(config, 8);
}

// Each frame's times over `frames` calls after a warm-up of at least kRenderWarmupFrames frames and
// kRenderWarmup: NVIDIA's driver takes about a second of steady load to raise the GPU's clock, longer than a
// case's frames take, so a shorter warm-up timed each case at whatever clock the one before left (345 to
// 1845 MHz from run to run). before(i) runs untimed (the wait for the engine's
// next result is the other thread's, not this one's), draw(i) is timed and ended by glFinish (llvmpipe
// draws asynchronously).
struct FrameTimes {
    base::RollingStats wall, cpu, gpu, clock;
    int firstMeasured = -1; // the index of the first frame after the warm-up
    GlFrameMs medians() const {
        return {wall.median(), cpu.median(), gpu.median(), clock.count() > 0 ? clock.median() : 0.0};
    }
};

template <class Before, class Draw> FrameTimes timeFrames(int frames, Before&& before, Draw&& draw) {
    const auto n = static_cast<std::size_t>(frames);
    FrameTimes t{base::RollingStats(n), base::RollingStats(n), base::RollingStats(n), base::RollingStats(n)};
    const render::gl::Query query = render::gl::Query::create();
    const auto warmupEnd = Clock::now() + kRenderWarmup;
    for (int i = 0; t.wall.count() < n; ++i) {
        const bool warmingUp = i < kRenderWarmupFrames || Clock::now() < warmupEnd;
        if (!warmingUp && t.firstMeasured < 0)
            t.firstMeasured = i;
        before(i);
        const auto start = Clock::now();
        const double cpuStart = base::threadCpuMs();
        glBeginQuery(GL_TIME_ELAPSED, query.id());
        draw(i);
        glEndQuery(GL_TIME_ELAPSED);
        const double cpuMs = base::threadCpuMs() - cpuStart;
        glFinish();
        GLuint64 gpuNs = 0;
        glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &gpuNs);
        if (warmingUp)
            continue;
        t.wall.add(msSince(start));
        t.cpu.add(cpuMs);
        t.gpu.add(static_cast<double>(gpuNs) * 1e-6);
        if (const auto& clock = currentGpuClock())
            if (const auto mhz = clock->graphicsMhz())
                t.clock.add(*mhz);
    }
    return t;
}

template <class Draw> FrameTimes timeFrames(int frames, Draw&& draw) {
    return timeFrames(
        frames, [](int) {}, std::forward<Draw>(draw));
}

} // namespace

const std::optional<GpuClock>& currentGpuClock() {
    static const std::optional<GpuClock> clock =
        GpuClock::open(reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    return clock;
}

std::string gpuClockText(double mhz) {
    const auto& clock = currentGpuClock();
    if (!clock || mhz <= 0.0)
        return "";
    char text[64];
    std::snprintf(text, sizeof text, " at a GPU clock of %.0f of %u MHz", mhz, clock->maxGraphicsMhz());
    return text;
}

GlFrameMs bareGlPoints(const processing::ShownFrame& shown, int width, int height, int frames,
                       double paceFps) {
    render::PointCloudRenderer renderer;
    render::FrameTextures textures;
    render::RenderTarget target;
    if (!renderer.init() || !target.resize(width, height) || !shown.depth.data)
        return {};
    textures.uploadDepth(shown.depth);
    textures.uploadColours(shown.pointColours.get());
    render::CloudParams params;
    const float fov = render::verticalFovRadians(shown.depth.intrinsics);
    const auto period =
        paceFps > 0.0
            ? std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / paceFps))
            : Clock::duration::zero();
    Clock::time_point next = Clock::now();
    return timeFrames(
               frames,
               [&](int) {
                   std::this_thread::sleep_until(next);
                   next = std::max(next + period, Clock::now());
               },
               [&](int i) {
                   params.viewProjection = render::cloudViewProjection({0.01f * i, 0.1f, 1.0f, {}}, 1.2f, fov,
                                                                       float(width) / float(height));
                   renderer.render(target, textures, params);
               })
        .medians();
}

namespace {

// A --breakdown run: the GL points frame again with one part of the default view left out, so that the
// difference is what that part costs.
struct Variant {
    const char* name;
    void (*change)(ui::Settings&);
};
constexpr Variant kBreakdown[] = {
    {"without fill gaps", [](ui::Settings& s) { s.cloud.fillGaps = false; }},
    {"without the 2D panels",
     [](ui::Settings& s) { s.panels.depth = s.panels.confidence = s.panels.camera = false; }},
    {"without the depth panel", [](ui::Settings& s) { s.panels.depth = false; }},
    {"without the confidence panel", [](ui::Settings& s) { s.panels.confidence = false; }},
    {"without the camera panel", [](ui::Settings& s) { s.panels.camera = false; }},
    {"without the controls", [](ui::Settings& s) { s.panels.controls = false; }},
    {"every sample (no decimation)", [](ui::Settings& s) { s.cloud.decimation = 1; }},
};

Expected<PathResult> runPath(const BenchCase& c, render::CloudPath path, const BenchOptions& o,
                             CaseResult& result, const Variant* variant = nullptr) {
    auto frames = makeFrames(c);
    if (frames.empty())
        return Error{"cannot make synthetic frames"};
    const frame::FramePtr last = frames.back();
    auto device =
        std::make_unique<devices::FrameListDevice>(std::move(frames), o.sourceFps, "synthetic frames");
    ui::HeadlessUi gui;
    if (Status s = gui.init(o.width, o.height); !s)
        return s.error();
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return s.error();
    gui.setDrawsChangedFramesWhole(!renderer.softwareGl()); // as the window presents
    ui::Settings settings;
    settings.panels.stats = false; // a bench measures the viewer, not its own plots
    settings.cloud.path =
        path == render::CloudPath::Splat ? ui::CloudPathChoice::Splat : ui::CloudPathChoice::Points;
    settings.cloud.motion.enabled = true;
    settings.processing.upsampling = c.upsampling;
    if (variant)
        variant->change(settings);
    engine::Instrument instrument(std::move(device), "synthetic frames");
    ui::Viewer viewer(instrument, renderer, settings);
    instrument.start();
    // The GL thread's time: the wait for the engine's next result is the other thread's, not this one's.
    const FrameTimes ms = timeFrames(
        o.frames, [&](int) { viewer.awaitFrame(std::chrono::milliseconds(500)); },
        [&](int i) {
            gui.newFrame(1.0f / 60.0f);
            viewer.update(i / 60.0);
            viewer.drawUi();
            gui.renderIfChanged(renderer.contentVersion());
        });
    const processing::ShownFramePtr shown = viewer.shown();
    PathResult r{path,
                 variant ? variant->name : "",
                 ms.wall.median(),
                 percentile(ms.wall, 0.9),
                 ms.cpu.median(),
                 ms.gpu.median(),
                 ms.medians().gpuClockMhz,
                 viewer.summary().pointsDrawn,
                 shown ? shown->cloud.factor : 1,
                 viewer.summary().stages};
    if (path == render::CloudPath::Points && shown && !variant) {
        // The floor: the same window composited again with nothing new to draw and the source idle, as
        // when a replay is paused (a source that delivers once in 1000 s; its one frame is processed before
        // timing starts).
        instrument.switchSource(std::make_unique<devices::FrameListDevice>(std::vector{last}, 0.001, "idle"),
                                "idle");
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        result.floor = timeFrames(o.frames, [&](int) {
                           gui.newFrame(1.0f / 60.0f);
                           viewer.drawUi();
                           gui.render();
                       }).medians();
        // The same still view as the window runs it: the viewer's update and the ImGui frame, and the
        // composite only if the picture changed (it does not: nothing moves).
        viewer.settings().cloud.motion.enabled = false;
        std::vector<bool> drawn;
        const FrameTimes still = timeFrames(o.frames, [&](int i) {
            gui.newFrame(1.0f / 60.0f);
            viewer.update(i / 60.0);
            viewer.drawUi();
            drawn.push_back(gui.renderIfChanged(renderer.contentVersion()));
        });
        result.stillMs = still.wall.median();
        result.stillDrawn =
            static_cast<int>(std::count(drawn.begin() + still.firstMeasured, drawn.end(), true));
        result.cloudWidth = renderer.cloudTarget().width();
        result.cloudHeight = renderer.cloudTarget().height();
        result.shownSamples = static_cast<std::size_t>(shown->depth.width()) * shown->depth.height();
        result.bare = bareGlPoints(*shown, result.cloudWidth, result.cloudHeight, o.frames);
        result.barePaced = bareGlPoints(*shown, result.cloudWidth, result.cloudHeight, o.frames, o.sourceFps);
    }
    return r;
}

std::string glFrameText(const GlFrameMs& t) {
    char text[96];
    std::snprintf(text, sizeof text, "%.2f ms (GL thread's CPU %.2f, GPU %.2f", t.wall, t.cpu, t.gpu);
    return text + gpuClockText(t.gpuClockMhz) + ")";
}

void printResult(const CaseResult& r, const BenchOptions& o) {
    std::printf("%s (%zu samples) in a %dx%d window (cloud panel %dx%d), every panel shown, %d frames:\n",
                r.c.name, r.shownSamples, o.width, o.height, r.cloudWidth, r.cloudHeight, o.frames);
    std::printf("  floor (composite, nothing new) %s\n  bare GL_POINTS of every sample %s back to back, "
                "%s at %.0f fps\n",
                glFrameText(r.floor).c_str(), glFrameText(r.bare).c_str(), glFrameText(r.barePaced).c_str(),
                o.sourceFps);
    std::printf("  still view (paused, nothing moves, kept: drawn %d of %d) %.3f ms\n", r.stillDrawn,
                o.frames, r.stillMs);
    for (const PathResult& p : r.paths) {
        std::printf(
            "  %-10s frame median %s, p90 %.2f ms = %.0f fps; %.2fx bare GL_POINTS (GPU %.2fx), %.2fx "
            "bare at the same pace (GPU %.2fx); %llu points at %dx decimation\n   ",
            (std::string(render::toString(p.path)) + (p.variant.empty() ? "" : ", " + p.variant)).c_str(),
            glFrameText({p.medianMs, p.cpuMs, p.gpuMs, p.gpuClockMhz}).c_str(), p.p90Ms, 1000.0 / p.medianMs,
            p.medianMs / r.bare.wall, p.gpuMs / r.bare.gpu, p.medianMs / r.barePaced.wall,
            p.gpuMs / r.barePaced.gpu, static_cast<unsigned long long>(p.points), p.decimation);
        for (const auto& s : p.stages)
            std::printf(" %s %.2f", s.name.c_str(), s.medianMs);
        std::printf("\n");
    }
}

nlohmann::json toJson(const GlFrameMs& t) {
    return {{"wallMs", t.wall}, {"glThreadCpuMs", t.cpu}, {"gpuMs", t.gpu}, {"gpuClockMhz", t.gpuClockMhz}};
}

nlohmann::json toJson(const CaseResult& r) {
    nlohmann::json paths = nlohmann::json::array();
    for (const PathResult& p : r.paths) {
        nlohmann::json stages = nlohmann::json::object();
        for (const auto& s : p.stages)
            stages[s.name] = s.medianMs;
        paths.push_back({{"path", render::toString(p.path)},
                         {"variant", p.variant},
                         {"frameMedianMs", p.medianMs},
                         {"frameP90Ms", p.p90Ms},
                         {"frameGlThreadCpuMs", p.cpuMs},
                         {"frameGpuMs", p.gpuMs},
                         {"gpuClockMhz", p.gpuClockMhz},
                         {"vsBareGlPoints", p.medianMs / r.bare.wall},
                         {"gpuVsBareGlPoints", p.gpuMs / r.bare.gpu},
                         {"vsBareGlPointsPaced", p.medianMs / r.barePaced.wall},
                         {"gpuVsBareGlPointsPaced", p.gpuMs / r.barePaced.gpu},
                         {"points", p.points},
                         {"decimation", p.decimation},
                         {"stageMedianMs", stages}});
    }
    return {{"case", r.c.name},
            {"samples", r.shownSamples},
            {"cloudPanel", {r.cloudWidth, r.cloudHeight}},
            {"floorMs", r.floor.wall},
            {"floor", toJson(r.floor)},
            {"stillViewMs", r.stillMs},
            {"stillViewFramesDrawn", r.stillDrawn},
            {"bareGlPointsMs", r.bare.wall},
            {"bareGlPoints", toJson(r.bare)},
            {"bareGlPointsPaced", toJson(r.barePaced)},
            {"paths", paths}};
}

} // namespace

int runBenchRender(const BenchOptions& options) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    std::printf("bench render on %s, frames arriving at %.0f fps\n", context->rendererName().c_str(),
                options.sourceFps);
    nlohmann::json results = nlohmann::json::array();
    for (const BenchCase& c :
         {BenchCase{"256x192", 256, 192, false}, BenchCase{"640x480", 640, 480, false},
          BenchCase{"960x720", 960, 720, false}, BenchCase{"1280x720", 1280, 720, false},
          BenchCase{"256x192 upsampled", 256, 192, true}, BenchCase{"1920x1440", 1920, 1440, false}}) {
        CaseResult result;
        result.c = c;
        for (const render::CloudPath path : {render::CloudPath::Points, render::CloudPath::Splat}) {
            auto r = runPath(c, path, options, result);
            if (!r) {
                std::fprintf(stderr, "depthcloud: error: %s\n", r.error().message.c_str());
                return kExitFailure;
            }
            result.paths.push_back(std::move(*r));
        }
        for (const Variant& v : kBreakdown) {
            if (!options.breakdown)
                break;
            auto r = runPath(c, render::CloudPath::Points, options, result, &v);
            if (!r) {
                std::fprintf(stderr, "depthcloud: error: %s\n", r.error().message.c_str());
                return kExitFailure;
            }
            result.paths.push_back(std::move(*r));
        }
        printResult(result, options);
        results.push_back(toJson(result));
    }
    if (!options.jsonPath.empty()) {
        if (Status s = base::writeTextFile(options.jsonPath, results.dump(2) + "\n"); !s) {
            std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
            return kExitFailure;
        }
    }
    return kExitOk;
}

} // namespace dc::tool
