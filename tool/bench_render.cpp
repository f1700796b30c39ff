#include "base/files.h"
#include "base/log.h"
#include "base/rolling_stats.h"
#include "devices/frame_list_device.h"
#include "devices/synthetic/synthetic_device.h"
#include "frame/image_io.h"
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

constexpr int kWarmupFrames = 20;
constexpr double kTargetMs = 1000.0 / 60.0;

struct BenchCase {
    int depthWidth;
    int depthHeight;
    double bareGlPointsBaselineMs; // the measurement of bare GL_POINTS on this machine's llvmpipe
};

struct CaseResult {
    BenchCase c;
    double medianMs = 0, maxMs = 0;
    std::vector<engine::StageSummary> stages;
};

// Eight distinct noisy frames, made before timing starts so the capture thread costs nothing while the
// viewer is measured; every viewer frame gets a new device frame (upload + panels + cloud each time).
std::vector<frame::FramePtr> makeFrames(const BenchCase& c) {
    devices::SyntheticConfig config;
    config.depthWidth = c.depthWidth;
    config.depthHeight = c.depthHeight;
    config.paced = false;
    devices::SyntheticDevice device(config);
    std::vector<frame::FramePtr> frames;
    if (!device.open() || !device.start())
        return frames;
    for (int i = 0; i < 8; ++i)
        frames.push_back(device.capture(std::chrono::seconds(1)).frame);
    return frames;
}

Expected<CaseResult> runCase(const BenchCase& c, const BenchOptions& o) {
    auto frames = makeFrames(c);
    if (frames.empty())
        return Error{"cannot make synthetic frames"};
    auto device = std::make_unique<devices::FrameListDevice>(std::move(frames), 1000.0, "synthetic frames");
    ui::HeadlessUi gui;
    if (Status s = gui.init(o.width, o.height); !s)
        return s.error();
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return s.error();
    engine::Instrument instrument(std::move(device), "synthetic frames");
    ui::Viewer viewer(instrument, renderer, ui::Settings{});
    instrument.start();
    base::RollingStats frameMs(static_cast<std::size_t>(o.frames));
    for (int i = 0; i < kWarmupFrames + o.frames; ++i) {
        const auto start = Clock::now();
        gui.newFrame(1.0f / 60.0f);
        viewer.update(i / 60.0, std::chrono::milliseconds(100));
        viewer.drawUi();
        gui.render();
        glFinish(); // llvmpipe renders asynchronously: count the frame only once it is really drawn
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        if (i >= kWarmupFrames)
            frameMs.add(ms);
    }
    return CaseResult{c, frameMs.median(), frameMs.max(), viewer.summary().stages};
}

void printResult(const CaseResult& r, const BenchOptions& o) {
    std::printf("depth %dx%d in a %dx%d window, all panels shown, %d frames:\n", r.c.depthWidth,
                r.c.depthHeight, o.width, o.height, o.frames);
    std::printf("  frame median %.2f ms (max %.2f ms) = %.0f fps; target %.1f ms: %s (%.2fx of target)\n",
                r.medianMs, r.maxMs, 1000.0 / r.medianMs, kTargetMs,
                r.medianMs <= kTargetMs ? "met" : "MISSED", r.medianMs / kTargetMs);
    std::printf("  vs bare GL_POINTS baseline %.0f ms: %.2fx\n", r.c.bareGlPointsBaselineMs,
                r.medianMs / r.c.bareGlPointsBaselineMs);
    std::printf("  stage medians:");
    for (const auto& s : r.stages)
        std::printf(" %s %.2f ms", s.name.c_str(), s.medianMs);
    std::printf("\n");
}

} // namespace

int runBenchRender(const BenchOptions& options) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context) {
        std::fprintf(stderr, "depthcloud: error: %s\n", context.error().message.c_str());
        return kExitFailure;
    }
    std::printf("bench render on %s\n", context->rendererName().c_str());
    nlohmann::json results = nlohmann::json::array();
    for (const BenchCase& c : {BenchCase{256, 192, 11.0}, BenchCase{640, 480, 50.0}}) {
        auto r = runCase(c, options);
        if (!r) {
            std::fprintf(stderr, "depthcloud: error: %s\n", r.error().message.c_str());
            return kExitFailure;
        }
        printResult(*r, options);
        nlohmann::json stages = nlohmann::json::object();
        for (const auto& s : r->stages)
            stages[s.name] = s.medianMs;
        results.push_back({{"depth", std::to_string(c.depthWidth) + "x" + std::to_string(c.depthHeight)},
                           {"frameMedianMs", r->medianMs},
                           {"frameMaxMs", r->maxMs},
                           {"targetMs", kTargetMs},
                           {"bareGlPointsBaselineMs", c.bareGlPointsBaselineMs},
                           {"stageMedianMs", stages}});
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
