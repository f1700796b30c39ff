#include "tool/bench_instrument.h"

#include "base/files.h"
#include "base/log.h"
#include "base/rolling_stats.h"
#include "devices/synthetic/synthetic_device.h"
#include "frame/image_io.h"
#include "processing/accumulation_worker.h"
#include "processing/point_accumulator.h"
#include "processing/point_colours.h"
#include "render/accumulated_points.h"
#include "render/gl_context.h"
#include "tool/bench_median.h"
#include "tool/options.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kTargetMs = 1.0;

// Frames of the swaying synthetic camera, a quarter second apart, so consecutive poses differ.
std::vector<frame::FramePtr> movingFrames(int count) {
    devices::SyntheticConfig c;
    c.motion = true;
    c.cameraWidth = 640;
    c.cameraHeight = 480;
    const devices::SyntheticDevice device(c);
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < count; ++i)
        frames.push_back(device.makeFrame(static_cast<std::uint64_t>(i), 0.25 * i));
    return frames;
}

struct AccumulateResult {
    double addMedianMs = 0, addMaxMs = 0, syncMedianMs = 0, syncMaxMs = 0;
    std::size_t held = 0;
    double newPerFrame = 0;
};

struct RenderThreadResult {
    double medianMs = 0, maxMs = 0;
    std::uint64_t skipped = 0;
};

// The accumulation request of each frame, as the frame processor makes it: the raw depth, its colours.
std::vector<processing::AccumulationWorker::Request> requestsFor(const BenchInstrumentOptions& o,
                                                                 const std::vector<frame::FramePtr>& frames) {
    std::vector<processing::AccumulationWorker::Request> requests;
    for (const frame::FramePtr& f : frames) {
        const auto& d = f->sceneDepth->depthMeters;
        requests.push_back({std::shared_ptr<const frame::DepthData>(f, &*f->sceneDepth), f->depthIntrinsics(),
                            std::make_shared<const processing::RgbImage>(
                                processing::pointColours(f->capturedImage, d.width, d.height)),
                            *f->pose, frame::Confidence::Low, 0.1f,
                            static_cast<std::size_t>(o.budgetThousands) * 1000,
                            static_cast<float>(o.voxelMillimetres * 1e-3)});
    }
    return requests;
}

// What the viewer's frame pays in accumulate mode: handing the frame to the worker and uploading what it
// added, at a camera's 30 fps, with the worker adding on the other core.
RenderThreadResult benchRenderThread(const BenchInstrumentOptions& o,
                                     const std::vector<frame::FramePtr>& frames) {
    processing::AccumulationWorker worker;
    render::AccumulatedPoints gpu;
    if (!gpu.init())
        return {};
    const auto requests = requestsFor(o, frames);
    const std::size_t budget = requests.front().budget;
    std::size_t next = 0;
    for (; worker.size() < budget && next < 4 * frames.size(); ++next) {
        worker.submit(requests[next % requests.size()]);
        worker.waitIdle();
    }
    const std::uint64_t skippedBefore = worker.skipped();
    base::RollingStats ms(static_cast<std::size_t>(o.frames));
    const auto sync = [&](processing::PointAccumulator& points) { gpu.sync(points); };
    auto due = Clock::now();
    for (int i = 0; i < o.frames; ++i, ++next) {
        std::this_thread::sleep_until(due += std::chrono::microseconds(33'333));
        const auto start = Clock::now();
        worker.submit(requests[next % requests.size()]);
        worker.tryRead(sync);
        glFinish();
        ms.add(msSince(start));
    }
    worker.waitIdle();
    return {ms.median(), ms.max(), worker.skipped() - skippedBefore};
}

AccumulateResult benchAccumulate(const BenchInstrumentOptions& o,
                                 const std::vector<frame::FramePtr>& frames) {
    const std::size_t budget = static_cast<std::size_t>(o.budgetThousands) * 1000;
    // With the default 1 mm voxel most samples are new, so the ring fills and then churns: the worst case.
    processing::PointAccumulator acc(budget, static_cast<float>(o.voxelMillimetres * 1e-3));
    render::AccumulatedPoints gpu;
    if (!gpu.init())
        return {};
    std::size_t fill = 0;
    while (acc.size() < budget && fill < 4 * frames.size())
        acc.add(*frames[fill++ % frames.size()], frame::Confidence::Low, 0.1f);
    gpu.sync(acc);
    base::RollingStats add(static_cast<std::size_t>(o.frames)), sync(static_cast<std::size_t>(o.frames));
    std::size_t added = 0;
    for (int i = 0; i < o.frames; ++i) {
        auto start = Clock::now();
        added += acc.add(*frames[static_cast<std::size_t>(i) % frames.size()], frame::Confidence::Low, 0.1f);
        add.add(msSince(start));
        start = Clock::now();
        gpu.sync(acc);
        glFinish();
        sync.add(msSince(start));
    }
    return {add.median(), add.max(),  sync.median(),
            sync.max(),   acc.size(), static_cast<double>(added) / o.frames};
}

// The stats panel's cost: gathering its figures from the viewer and drawing it, inside a real ImGui frame.
std::pair<double, double> benchStatsPanel(const BenchInstrumentOptions& o) {
    ui::HeadlessUi gui;
    devices::SyntheticConfig c;
    c.cameraWidth = 640;
    c.cameraHeight = 480;
    render::ViewRenderer renderer;
    if (!gui.init(1280, 720) || !renderer.init())
        return {0, 0};
    engine::Instrument instrument(std::make_unique<devices::SyntheticDevice>(c), "synthetic");
    ui::Viewer viewer(instrument, renderer, ui::Settings{});
    instrument.start();
    base::RollingStats ms(static_cast<std::size_t>(o.frames));
    for (int i = 0; i < o.frames + 20; ++i) {
        gui.newFrame(1.0f / 60.0f);
        viewer.update(i / 60.0, std::chrono::milliseconds(50));
        const auto start = Clock::now();
        bool open = true;
        ui::drawStatsPanel(viewer.statsView(), &open);
        if (i >= 20)
            ms.add(msSince(start));
        gui.render();
    }
    return {ms.median(), ms.max()};
}

} // namespace

CLI::App* addBenchInstrumentCommand(CLI::App& bench, BenchInstrumentOptions& o) {
    CLI::App* cmd =
        bench.add_subcommand("instrument", "per-frame cost of accumulate mode and the stats panel");
    cmd->add_option("--frames", o.frames, "measured frames")
        ->check(CLI::Range(10, 100000))
        ->capture_default_str();
    cmd->add_option("--budget", o.budgetThousands, "accumulate budget in thousands of points")
        ->check(CLI::Range(10, 4000))
        ->capture_default_str();
    cmd->add_option("--voxel-mm", o.voxelMillimetres, "accumulate voxel size in millimetres")
        ->check(CLI::Range(0.5, 100.0))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

int runBenchInstrument(const BenchInstrumentOptions& o) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    const auto frames = movingFrames(24);
    if (frames.empty()) {
        std::fprintf(stderr, "depthcloud: error: cannot make synthetic frames\n");
        return kExitFailure;
    }
    const AccumulateResult a = benchAccumulate(o, frames);
    std::printf("bench instrument on %s, 256x192 depth, %d frames\n", context->rendererName().c_str(),
                o.frames);
    std::printf("  accumulate add (%.1f mm voxels): median %.3f ms (max %.3f) at %zu points held, %.0f new "
                "points per frame\n",
                o.voxelMillimetres, a.addMedianMs, a.addMaxMs, a.held, a.newPerFrame);
    std::printf("  accumulate GPU upload: median %.3f ms (max %.3f)\n", a.syncMedianMs, a.syncMaxMs);
    std::printf("  add + upload: %.3f ms of CPU per frame (the work, now on the accumulation worker)\n",
                a.addMedianMs + a.syncMedianMs);
    const RenderThreadResult r = benchRenderThread(o, frames);
    std::printf(
        "  accumulate on the render thread at 30 fps (hand-over + upload): median %.3f ms (max %.3f), "
        "%llu of %d frames skipped by the worker; target %.1f ms: %s (%.2fx)\n",
        r.medianMs, r.maxMs, static_cast<unsigned long long>(r.skipped), o.frames, kTargetMs,
        r.medianMs <= kTargetMs ? "met" : "MISSED", r.medianMs / kTargetMs);
    const auto [statsMedian, statsMax] = benchStatsPanel(o);
    std::printf("  stats panel: median %.3f ms (max %.3f); target %.1f ms: %s\n", statsMedian, statsMax,
                kTargetMs, statsMedian <= kTargetMs ? "met" : "MISSED");
    if (o.jsonPath.empty())
        return kExitOk;
    const nlohmann::json j{{"voxelMillimetres", o.voxelMillimetres},
                           {"accumulateAddMedianMs", a.addMedianMs},
                           {"accumulateAddMaxMs", a.addMaxMs},
                           {"accumulateSyncMedianMs", a.syncMedianMs},
                           {"accumulateRenderThreadMedianMs", r.medianMs},
                           {"accumulateRenderThreadMaxMs", r.maxMs},
                           {"accumulateFramesSkipped", r.skipped},
                           {"pointsHeld", a.held},
                           {"newPointsPerFrame", a.newPerFrame},
                           {"statsPanelMedianMs", statsMedian},
                           {"statsPanelMaxMs", statsMax}};
    if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
