#include "tool/bench_engine.h"

#include "base/clock.h"
#include "base/files.h"
#include "base/log.h"
#include "devices/frame_list_device.h"
#include "devices/synthetic/synthetic_device.h"
#include "engine/instrument.h"
#include "engine/processing_graph.h"
#include "render/gl_context.h"
#include "render/view_renderer.h"
#include "tool/bench_median.h"
#include "tool/bench_settings.h"
#include "tool/options.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kEngineWarmupFrames = 30;
constexpr int kEngineDistinctFrames = 8;

nlohmann::json toJson(const Spread& s) {
    return {{"median", s.median}, {"p99", s.p99}};
}

// ARKit-like frames (256x192 depth, 1920x1440 camera) of the swaying synthetic camera, without sensor
// confidence as from a live camera, so the confidence estimate has work too.
std::vector<frame::FramePtr> benchFrames() {
    devices::SyntheticConfig c;
    c.motion = true;
    devices::SyntheticDevice device(c);
    std::vector<frame::FramePtr> frames;
    if (!device.open())
        return frames;
    for (int i = 0; i < kEngineDistinctFrames; ++i) {
        auto f = std::make_shared<frame::Frame>(*device.makeFrame(static_cast<std::uint64_t>(i), i / 60.0));
        f->sceneDepth->confidence = {};
        frames.push_back(std::move(f));
    }
    return frames;
}

struct EngineResult {
    std::vector<double> glCpuMs, updateCpuMs, uiCpuMs, glFrameCpuMs, glWallMs, latencyMs;
    engine::FrameCounts frames;
    engine::ProcessorCounts processor;
    std::uint64_t sourceDropped = 0;
    std::vector<engine::StageSummary> stages;
    engine::Demand demand;
};

// The viewer as the tool runs it, at viewerFps, on frames arriving at sourceFps.
Expected<EngineResult> runEngine(const BenchEngineOptions& o, std::vector<frame::FramePtr> frames) {
    ui::HeadlessUi gui;
    if (Status s = gui.init(1280, 720); !s)
        return s.error();
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return s.error();
    engine::Instrument instrument(std::make_unique<devices::FrameListDevice>(std::move(frames), o.sourceFps),
                                  "bench frames");
    ui::Viewer viewer(instrument, renderer, everyStageSettings());
    instrument.start();
    EngineResult r;
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.viewerFps));
    auto due = Clock::now();
    engine::FrameCounts framesBefore;
    engine::ProcessorCounts before;
    for (int i = 0; i < kEngineWarmupFrames + o.frames; ++i) {
        if (i == kEngineWarmupFrames) {
            framesBefore = instrument.status().frames;
            before = instrument.processor().counts();
        }
        std::this_thread::sleep_until(due += period);
        const auto wall = Clock::now();
        const double cpu = base::threadCpuMs();
        gui.newFrame(static_cast<float>(1.0 / o.viewerFps));
        viewer.update(i / o.viewerFps);
        const double updated = base::threadCpuMs();
        viewer.drawUi();
        const double glCpu = base::threadCpuMs() - cpu;
        const double glWall = msSince(wall);
        gui.render();
        glFinish();
        viewer.presented();
        if (i >= kEngineWarmupFrames) {
            r.glCpuMs.push_back(glCpu);
            r.updateCpuMs.push_back(updated - cpu);
            r.uiCpuMs.push_back(cpu + glCpu - updated);
            r.glWallMs.push_back(glWall);
            r.glFrameCpuMs.push_back(base::threadCpuMs() - cpu);
        }
    }
    const engine::FrameCounts after = instrument.status().frames;
    const engine::ProcessorCounts p = instrument.processor().counts();
    r.frames = {after.delivered - framesBefore.delivered, after.shown - framesBefore.shown,
                after.dropped - framesBefore.dropped, after.deliveredPerSecond, after.shownPerSecond};
    r.processor = {p.framesProcessed - before.framesProcessed, p.redone - before.redone,
                   p.framesUnshown - before.framesUnshown, p.framesSkipped - before.framesSkipped,
                   p.resultsTaken - before.resultsTaken};
    r.sourceDropped = r.frames.dropped - r.processor.framesUnshown - r.processor.framesSkipped;
    r.latencyMs = instrument.processor().latencyMs().inOrder();
    r.stages = instrument.stages().all();
    r.demand = viewer.demand();
    return r;
}

struct InlineResult {
    std::vector<double> cpuMs, wallMs;
};

// The same frames and demand, processed on this thread one after the other: what the viewer's GL thread
// did per frame before the frame processor existed.
InlineResult runInline(const BenchEngineOptions& o, const std::vector<frame::FramePtr>& frames,
                       const engine::Demand& demand) {
    engine::ProcessingGraph graph;
    InlineResult r;
    for (int i = 0; i < kEngineWarmupFrames + o.frames; ++i) {
        auto f = std::make_shared<frame::Frame>(*frames[static_cast<std::size_t>(i) % frames.size()]);
        f->sequence = static_cast<std::uint64_t>(i);
        f->timestampNs = static_cast<std::int64_t>(i + 1) * 16'666'667;
        const auto wall = Clock::now();
        const double cpu = base::threadCpuMs();
        const processing::ShownFramePtr shown = graph.run(f, demand, 1, true);
        if (i >= kEngineWarmupFrames) {
            r.cpuMs.push_back(base::threadCpuMs() - cpu);
            r.wallMs.push_back(msSince(wall));
        }
    }
    return r;
}

} // namespace

CLI::App* addBenchEngineCommand(CLI::App& bench, BenchEngineOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "engine",
        "GL-thread CPU per frame with every stage on, processing latency, frames processed vs shown");
    cmd->add_option("--frames", o.frames, "measured viewer frames")
        ->check(CLI::Range(20, 100000))
        ->capture_default_str();
    cmd->add_option("--source-fps", o.sourceFps, "frames per second the source delivers")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    cmd->add_option("--viewer-fps", o.viewerFps, "frames per second the viewer draws")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

int runBenchEngine(const BenchEngineOptions& o) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    const std::vector<frame::FramePtr> frames = benchFrames();
    if (frames.empty()) {
        std::fprintf(stderr, "depthcloud: error: cannot make synthetic frames\n");
        return kExitFailure;
    }
    auto engineRun = runEngine(o, frames);
    if (!engineRun) {
        std::fprintf(stderr, "depthcloud: error: %s\n", engineRun.error().message.c_str());
        return kExitFailure;
    }
    const EngineResult& e = *engineRun;
    const InlineResult in = runInline(o, frames, e.demand);
    const Spread glCpu = spreadOf(e.glCpuMs), glFrameCpu = spreadOf(e.glFrameCpuMs),
                 glWall = spreadOf(e.glWallMs);
    const Spread updateCpu = spreadOf(e.updateCpuMs), uiCpu = spreadOf(e.uiCpuMs);
    const Spread latency = spreadOf(e.latencyMs), inCpu = spreadOf(in.cpuMs), inWall = spreadOf(in.wallMs);

    std::printf(
        "bench engine on %s: 256x192 depth, 1920x1440 camera, every stage on; source %.0f fps, viewer "
        "%.0f fps, %d frames\n",
        context->rendererName().c_str(), o.sourceFps, o.viewerFps, o.frames);
    std::printf(
        "  GL thread, hand-over + uploads + draw calls + UI (thread CPU): median %.3f ms, p99 %.3f ms\n",
        glCpu.median, glCpu.p99);
    std::printf("    of which viewer.update (hand-over, uploads, panel and cloud draw calls, with llvmpipe's "
                "vertex work on this thread): median %.3f ms, p99 %.3f ms\n",
                updateCpu.median, updateCpu.p99);
    std::printf("    of which the UI's panels (ImGui, no driver): median %.3f ms, p99 %.3f ms\n",
                uiCpu.median, uiCpu.p99);
    std::printf("  GL thread, whole frame incl. ImGui render and glFinish (thread CPU): median %.3f ms, p99 "
                "%.3f ms\n",
                glFrameCpu.median, glFrameCpu.p99);
    std::printf("  inline on the calling thread (the old viewer's processing per frame): CPU median %.3f ms, "
                "p99 %.3f ms; wall median %.3f ms, p99 %.3f ms\n",
                inCpu.median, inCpu.p99, inWall.median, inWall.p99);
    std::printf(
        "  GL-thread work per frame, inline (processing wall + engine GL CPU) / engine GL CPU: %.1fx\n",
        (inWall.median + glCpu.median) / glCpu.median);
    std::printf(
        "  processing latency, frame arrival -> result ready: median %.2f ms, p99 %.2f ms (last %zu)\n",
        latency.median, latency.p99, e.latencyMs.size());
    std::printf(
        "  frames: delivered %llu, processed %llu, shown %llu; dropped %llu (%llu processed but replaced "
        "before shown, %llu replaced before processing)\n",
        static_cast<unsigned long long>(e.frames.delivered),
        static_cast<unsigned long long>(e.processor.framesProcessed),
        static_cast<unsigned long long>(e.frames.shown), static_cast<unsigned long long>(e.frames.dropped),
        static_cast<unsigned long long>(e.processor.framesUnshown),
        static_cast<unsigned long long>(e.sourceDropped));
    // The GL thread's own stages (upload, panels, cloud) are among them: the upload is the part of
    // viewer.update that is not a draw.
    std::printf("  stage medians, wall (the processor's, and the GL thread's upload, panels, cloud):");
    for (const engine::StageSummary& s : e.stages)
        std::printf(" %s %.2f ms", s.name.c_str(), s.medianMs);
    std::printf("\n");
    if (o.jsonPath.empty())
        return kExitOk;
    nlohmann::json stages = nlohmann::json::object();
    for (const engine::StageSummary& s : e.stages)
        stages[s.name] = s.medianMs;
    const nlohmann::json j{
        {"renderer", context->rendererName()},
        {"depth", "256x192"},
        {"camera", "1920x1440"},
        {"sourceFps", o.sourceFps},
        {"viewerFps", o.viewerFps},
        {"frames", o.frames},
        {"engine",
         {{"glThreadCpuMs", toJson(glCpu)},
          {"glThreadUpdateCpuMs", toJson(updateCpu)},
          {"glThreadUiCpuMs", toJson(uiCpu)},
          {"glThreadWallMs", toJson(glWall)},
          {"glThreadFrameCpuMs", toJson(glFrameCpu)},
          {"processingLatencyMs", toJson(latency)},
          {"latencySamples", e.latencyMs.size()},
          {"delivered", e.frames.delivered},
          {"processed", e.processor.framesProcessed},
          {"shown", e.frames.shown},
          {"dropped", e.frames.dropped},
          {"processedNotShown", e.processor.framesUnshown},
          {"droppedBeforeProcessing", e.sourceDropped},
          {"skipped", e.processor.framesSkipped},
          {"redone", e.processor.redone},
          {"stageMedianMs", stages}}},
        {"inline", {{"processingCpuMs", toJson(inCpu)}, {"processingWallMs", toJson(inWall)}}},
        {"glThreadInlineOverEngine", (inWall.median + glCpu.median) / glCpu.median}};
    if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
