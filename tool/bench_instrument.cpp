#include "tool/bench_instrument.h"

#include "devices/image_io.h"
#include "devices/log.h"
#include "devices/synthetic_device.h"
#include "processing/point_accumulator.h"
#include "processing/rolling_stats.h"
#include "render/accumulated_points.h"
#include "render/gl_context.h"
#include "tool/options.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kTargetMs = 1.0;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Frames of the swaying synthetic camera, a quarter second apart, so consecutive poses differ.
std::vector<devices::FramePtr> movingFrames(int count) {
    devices::SyntheticConfig c;
    c.motion = true;
    c.cameraWidth = 640;
    c.cameraHeight = 480;
    const devices::SyntheticDevice device(c);
    std::vector<devices::FramePtr> frames;
    for (int i = 0; i < count; ++i)
        frames.push_back(device.makeFrame(static_cast<std::uint64_t>(i), 0.25 * i));
    return frames;
}

struct AccumulateResult {
    double addMedianMs = 0, addMaxMs = 0, syncMedianMs = 0, syncMaxMs = 0;
    std::size_t held = 0;
    double newPerFrame = 0;
};

AccumulateResult benchAccumulate(const BenchInstrumentOptions& o,
                                 const std::vector<devices::FramePtr>& frames) {
    const std::size_t budget = static_cast<std::size_t>(o.budgetThousands) * 1000;
    // With the default 1 mm voxel most samples are new, so the ring fills and then churns: the worst case.
    processing::PointAccumulator acc(budget, static_cast<float>(o.voxelMillimetres * 1e-3));
    render::AccumulatedPoints gpu;
    if (!gpu.init())
        return {};
    std::size_t fill = 0;
    while (acc.size() < budget && fill < 4 * frames.size())
        acc.add(*frames[fill++ % frames.size()], devices::Confidence::Low, 0.1f);
    gpu.sync(acc);
    processing::RollingStats add(static_cast<std::size_t>(o.frames)),
        sync(static_cast<std::size_t>(o.frames));
    std::size_t added = 0;
    for (int i = 0; i < o.frames; ++i) {
        auto start = Clock::now();
        added +=
            acc.add(*frames[static_cast<std::size_t>(i) % frames.size()], devices::Confidence::Low, 0.1f);
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
    if (!gui.init(1280, 720))
        return {0, 0};
    ui::Viewer viewer(std::make_unique<devices::SyntheticDevice>(c), ui::Settings{});
    if (!viewer.init())
        return {0, 0};
    processing::RollingStats ms(static_cast<std::size_t>(o.frames));
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
    const double total = a.addMedianMs + a.syncMedianMs;
    std::printf("  accumulate total: %.3f ms per frame; target %.1f ms: %s (%.2fx)\n", total, kTargetMs,
                total <= kTargetMs ? "met" : "MISSED", total / kTargetMs);
    const auto [statsMedian, statsMax] = benchStatsPanel(o);
    std::printf("  stats panel: median %.3f ms (max %.3f); target %.1f ms: %s\n", statsMedian, statsMax,
                kTargetMs, statsMedian <= kTargetMs ? "met" : "MISSED");
    if (o.jsonPath.empty())
        return kExitOk;
    const nlohmann::json j{{"voxelMillimetres", o.voxelMillimetres},
                           {"accumulateAddMedianMs", a.addMedianMs},
                           {"accumulateAddMaxMs", a.addMaxMs},
                           {"accumulateSyncMedianMs", a.syncMedianMs},
                           {"pointsHeld", a.held},
                           {"newPointsPerFrame", a.newPerFrame},
                           {"statsPanelMedianMs", statsMedian},
                           {"statsPanelMaxMs", statsMax}};
    if (Status s = devices::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
