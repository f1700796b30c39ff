#include "tool/bench_soak.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/source_spec.h"
#include "engine/instrument.h"
#include "render/gl_context.h"
#include "render/view_renderer.h"
#include "tool/bench_settings.h"
#include "tool/options.h"
#include "ui/headless_ui.h"
#include "ui/viewer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace dc::tool {

namespace {

struct Sample {
    int frame = 0;
    double rssMiB = 0.0;
    int fds = 0;
};

double residentMiB() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

int openFds() {
    std::error_code ec;
    int n = 0;
    for (auto it = std::filesystem::directory_iterator("/proc/self/fd", ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
        ++n;
    return n;
}

// Shows `o.frames` new frames with every stage on, sampling as it goes.
Expected<std::vector<Sample>> soak(const BenchSoakOptions& o, std::unique_ptr<devices::Device> device) {
    ui::HeadlessUi gui;
    if (Status s = gui.init(1280, 720); !s)
        return s.error();
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return s.error();
    engine::Instrument instrument(std::move(device), o.source);
    ui::Settings settings = everyStageSettings();
    settings.accumulate.enabled = true;
    ui::Viewer viewer(instrument, renderer, settings);
    instrument.start();
    std::vector<Sample> samples;
    int shown = 0, idle = 0;
    while (shown < o.frames) {
        gui.newFrame(1.0f / 30.0f);
        const bool fresh = viewer.update(shown / 30.0, std::chrono::seconds(5));
        viewer.drawUi();
        gui.render();
        viewer.presented();
        idle = fresh ? 0 : idle + 1;
        if (idle > 20)
            return Error{"the source stopped delivering after " + std::to_string(shown) + " frames"};
        if (fresh && ++shown % o.sampleEvery == 0)
            samples.push_back({shown, residentMiB(), openFds()});
    }
    return samples;
}

} // namespace

CLI::App* addBenchSoakCommand(CLI::App& bench, BenchSoakOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "soak", "every stage on for many frames: resident memory and open files, sampled, and their growth");
    cmd->add_option("--frames", o.frames, "new frames shown")
        ->check(CLI::Range(100, 10000000))
        ->capture_default_str();
    cmd->add_option("--sample-every", o.sampleEvery, "frames between samples")
        ->check(CLI::Range(10, 1000000))
        ->capture_default_str();
    cmd->add_option("--warmup", o.warmupFrames, "frames before growth is measured")
        ->check(CLI::Range(0, 10000000))
        ->capture_default_str();
    cmd->add_option("--source", o.source, "any source; a replay should loop (replay:PATH:loop)")
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the samples and growth as JSON to this file");
    return cmd;
}

int runBenchSoak(const BenchSoakOptions& o) {
    if (o.warmupFrames + o.sampleEvery > o.frames) {
        std::fprintf(stderr, "depthcloud: error: --warmup: leaves no sample after it within --frames\n");
        return kExitBadArguments;
    }
    setLogQuiet(true);
    auto device = devices::openSourceSpec(o.source);
    if (!device) {
        std::fprintf(stderr, "depthcloud: error: --source: %s\n", device.error().message.c_str());
        return kExitBadArguments;
    }
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    const auto start = std::chrono::steady_clock::now();
    auto samples = soak(o, std::move(*device));
    if (!samples) {
        std::fprintf(stderr, "depthcloud: error: %s\n", samples.error().message.c_str());
        return kExitFailure;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto after = std::find_if(samples->begin(), samples->end(),
                                    [&](const Sample& s) { return s.frame >= o.warmupFrames; });
    const Sample base = *after;
    const auto most = std::max_element(after, samples->end(),
                                       [](const Sample& a, const Sample& b) { return a.rssMiB < b.rssMiB; });
    const double growth = (most->rssMiB - base.rssMiB) / base.rssMiB * 100.0;
    const int fdGrowth = samples->back().fds - base.fds;
    std::printf(
        "bench soak on %s: %s, every stage on (smoothing, upsampling, fog, aura, accumulate), %d frames "
        "in %.0f s\n",
        context->rendererName().c_str(), o.source.c_str(), o.frames, seconds);
    for (const Sample& s : *samples)
        std::printf("  frame %6d: resident %.1f MiB, %d open files\n", s.frame, s.rssMiB, s.fds);
    std::printf(
        "  after frame %d: resident memory grew %.2f %% at most (%.1f -> %.1f MiB), open files by %d\n",
        base.frame, growth, base.rssMiB, most->rssMiB, fdGrowth);
    if (o.jsonPath.empty())
        return kExitOk;
    nlohmann::json list = nlohmann::json::array();
    for (const Sample& s : *samples)
        list.push_back({{"frame", s.frame}, {"residentMiB", s.rssMiB}, {"openFiles", s.fds}});
    const nlohmann::json j{{"renderer", context->rendererName()},
                           {"source", o.source},
                           {"frames", o.frames},
                           {"seconds", seconds},
                           {"warmupFrames", base.frame},
                           {"residentGrowthPercent", growth},
                           {"openFilesGrowth", fdGrowth},
                           {"samples", list}};
    if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
