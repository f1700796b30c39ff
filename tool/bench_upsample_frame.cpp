// The per-frame figures of `depthcloud bench upsample`: the ARKit case against OpenCV's guided filter, the
// whole processing chain, and the temporal smoothing.

#include "base/clock.h"
#include "base/rolling_stats.h"
#include "devices/synthetic/synthetic_scene.h"
#include "processing/aura.h"
#include "processing/confidence_filter.h"
#include "processing/fog.h"
#include "processing/pipeline.h"
#include "processing/quality.h"
#include "tool/bench_upsample.h"

#include <chrono>
#include <cstdio>
#include <map>

namespace dc::tool::upsample {

namespace {

using Clock = std::chrono::steady_clock;

// Targets per ARKit frame, medians on this 2-core machine.
constexpr double kGlobalTargetMs = 10.0;      // the global smoother, real-time mode
constexpr double kFastTargetMs = 5.0;         // the fast guided filter, s = 4
constexpr double kChainFastTargetMs = 8.0;    // whole chain with the fast guided filter
constexpr double kChainGlobalTargetMs = 12.0; // whole chain with the global smoother
constexpr std::int64_t kFrameNs = 16'666'667;

struct Timed {
    double ms = 0, madMm = 0;
};

Timed timeMethod(const Method& m, const Problem& p, int runs) {
    frame::Plane<float> out = m.run(p);
    const double mad = processing::depthError(out, p.truth, &p.evaluated).mad * 1000.0;
    return {medianMilliseconds(runs, [&] { out = m.run(p); }), mad};
}

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::vector<frame::FramePtr> syntheticFrames(const BenchUpsampleOptions& o, int count) {
    const devices::SyntheticScene scene;
    const frame::Pose pose = devices::SyntheticScene::cameraPose(0.0, false);
    const int cw = o.quick ? 320 : 1920, ch = o.quick ? 240 : 1440, dw = o.quick ? 64 : 256,
              dh = o.quick ? 48 : 192;
    const frame::Intrinsics camera = devices::SyntheticScene::cameraIntrinsics(cw, ch);
    const frame::CapturedImage image = scene.renderImage(camera, pose);
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < count; ++i) {
        auto f = std::make_shared<frame::Frame>();
        f->sequence = static_cast<std::uint64_t>(i);
        f->capturedImage = image;
        f->cameraIntrinsics = camera;
        f->sceneDepth = scene.sensorDepth(camera.scaledTo(dw, dh), pose, static_cast<std::uint64_t>(i));
        frames.push_back(std::move(f));
    }
    return frames;
}

} // namespace

namespace {

const char* verdict(bool met) {
    return met ? "met" : "MISSED";
}

// The targets of the ARKit case at one thread count: the global smoother's time and its dominance of
// OpenCV's fast global smoother, the fast guided filter's time and its dominance of OpenCV's guided and
// joint bilateral filters.
nlohmann::json arkitTargets(const std::map<std::string, Timed>& t) {
    const Timed &global = t.at("ours global"), &fgs = t.at("opencv fast global smoother"),
                &fast = t.at("ours fast s=4"), &gf = t.at("opencv guided"),
                &jbf = t.at("opencv joint bilateral");
    const bool globalMet = global.ms <= kGlobalTargetMs, fastMet = fast.ms <= kFastTargetMs;
    const bool globalDominates = global.ms < fgs.ms && global.madMm < fgs.madMm;
    const bool fastDominates =
        fast.ms < gf.ms && fast.madMm < gf.madMm && fast.ms < jbf.ms && fast.madMm < jbf.madMm;
    std::printf(
        "    -> ours global %.2f ms, target <= %.0f ms: %s; %.1fx faster than OpenCV's fast global smoother "
        "at %.2fx its MAD: %s\n",
        global.ms, kGlobalTargetMs, verdict(globalMet), fgs.ms / global.ms, global.madMm / fgs.madMm,
        globalDominates ? "dominates" : "does NOT dominate");
    std::printf(
        "    -> ours fast s=4 %.2f ms, target <= %.0f ms: %s; %.1fx / %.1fx faster than OpenCV's guided / "
        "joint bilateral at %.2fx / %.2fx their MAD: %s\n",
        fast.ms, kFastTargetMs, verdict(fastMet), gf.ms / fast.ms, jbf.ms / fast.ms, fast.madMm / gf.madMm,
        fast.madMm / jbf.madMm, fastDominates ? "dominates both" : "does NOT dominate both");
    return {{"globalTargetMs", kGlobalTargetMs},
            {"globalMet", globalMet},
            {"globalDominatesFgs", globalDominates},
            {"fastTargetMs", kFastTargetMs},
            {"fastMet", fastMet},
            {"fastDominatesGfJbf", fastDominates}};
}

} // namespace

nlohmann::json benchArkitFrame(const BenchUpsampleOptions& options, const Problem& problem) {
    const int defaultThreads = cv::getNumThreads();
    const char* names[] = {"ours global",   "ours fast s=4",
                           "ours full",     "opencv fast global smoother",
                           "opencv guided", "opencv joint bilateral"};
    nlohmann::json out = nlohmann::json::array();
    std::printf("\nARKit case: %dx%d depth, %dx%d guide -> %dx%d, every method from the camera-size guide\n",
                problem.low.depthMeters.width, problem.low.depthMeters.height, problem.guideGray.cols,
                problem.guideGray.rows, problem.truth.width, problem.truth.height);
    for (int threads : {1, defaultThreads}) {
        cv::setNumThreads(threads);
        std::map<std::string, Timed> timed;
        nlohmann::json methods = nlohmann::json::object();
        std::printf("  %d thread(s):\n", threads);
        for (const char* name : names) {
            timed[name] = timeMethod(methodNamed(name), problem, options.runs);
            std::printf("    %-28s %8.2f ms  MAD %6.2f mm\n", name, timed[name].ms, timed[name].madMm);
            methods[name] = {{"medianMs", timed[name].ms}, {"madMm", timed[name].madMm}};
        }
        out.push_back({{"threads", threads}, {"methods", methods}, {"targets", arkitTargets(timed)}});
    }
    cv::setNumThreads(defaultThreads);
    return out;
}

namespace {

// The whole chain with `method` upsampling the shown smoothed depth, `measured` frames after a warm-up.
nlohmann::json benchChainWith(const BenchUpsampleOptions& options, processing::UpsamplingMethod method,
                              const char* label, double targetMs) {
    const std::vector<frame::FramePtr> frames = syntheticFrames(options, 8);
    processing::Pipeline pipeline = processing::makeDefaultPipeline();
    processing::ProcessingSettings settings;
    settings.smoothing = settings.upsampling = true;
    settings.upsamplingParams.method = method;
    const int measured = options.quick ? 10 : std::max(options.runs, 100), warmup = 10;
    std::map<std::string, base::RollingStats> parts;
    base::RollingStats total(static_cast<std::size_t>(measured)), cpu(static_cast<std::size_t>(measured));
    for (int i = 0; i < warmup + measured; ++i) {
        auto frame = std::make_shared<frame::Frame>(*frames[static_cast<std::size_t>(i) % frames.size()]);
        frame->timestampNs = i * kFrameNs;
        const double cpuStart = base::processCpuMs();
        const auto start = Clock::now();
        frame->sceneDepth->depthMeters =
            processing::filterByConfidence(*frame->sceneDepth, frame::Confidence::Medium);
        const double filterMs = millisecondsSince(start);
        const frame::FramePtr out = pipeline.run(frame, settings, {});
        const auto cloudStart = Clock::now();
        const std::size_t points = processing::countDrawablePoints(
            *processing::shownDepth(*out, settings.depthSource), frame::Confidence::Medium, 0.0f);
        const double cloudMs = millisecondsSince(cloudStart), totalMs = millisecondsSince(start);
        if (i < warmup || points == 0)
            continue;
        total.add(totalMs);
        cpu.add(base::processCpuMs() - cpuStart);
        parts["confidence filter"].add(filterMs);
        for (const processing::StageTiming& t : pipeline.lastTimings())
            parts[t.name].add(t.milliseconds);
        parts["cloud preparation"].add(cloudMs);
    }
    std::printf(
        "\nwhole chain per ARKit frame (confidence filter + smoothing + %s upsampling of the shown "
        "smoothed depth + cloud preparation), %zu frames:\n  median %.2f ms (max %.2f ms); target <= %.0f "
        "ms: %s\n  CPU time of all threads per frame, median %.2f ms (what the chain costs, whatever "
        "else the machine runs)\n  parts:",
        label, total.count(), total.median(), total.max(), targetMs, verdict(total.median() <= targetMs),
        cpu.median());
    nlohmann::json partsJson = nlohmann::json::object();
    for (const auto& [name, stats] : parts) {
        std::printf(" %s %.2f ms,", name.c_str(), stats.median());
        partsJson[name] = stats.median();
    }
    std::printf("\n");
    return {{"medianMs", total.median()},
            {"maxMs", total.max()},
            {"cpuMedianMs", cpu.median()},
            {"targetMs", targetMs},
            {"targetMet", total.median() <= targetMs},
            {"partsMedianMs", partsJson}};
}

} // namespace

nlohmann::json benchChain(const BenchUpsampleOptions& options) {
    return {{"fast", benchChainWith(options, processing::UpsamplingMethod::Fast, "fast guided filter (s = 4)",
                                    kChainFastTargetMs)},
            {"global", benchChainWith(options, processing::UpsamplingMethod::Global,
                                      "global smoother (real time)", kChainGlobalTargetMs)}};
}

nlohmann::json benchEffects(const BenchUpsampleOptions& options) {
    const frame::FramePtr raw = syntheticFrames(options, 1).front();
    processing::Pipeline pipeline = processing::makeDefaultPipeline();
    processing::ProcessingSettings settings;
    settings.upsampling = true;
    const frame::FramePtr upsampled = pipeline.run(raw, settings, {});
    const auto source = processing::DepthSource::Raw;
    nlohmann::json out = nlohmann::json::object();
    std::printf("\nfog and aura images (half the camera size), median of %d:\n", options.runs);
    for (const auto& [name, frame] :
         {std::pair{"sensor depth", raw}, std::pair{"upsampled depth", upsampled}}) {
        const double fogMs =
            medianMilliseconds(options.runs, [&] { processing::renderFog(*frame, {}, source); });
        const double auraMs =
            medianMilliseconds(options.runs, [&] { processing::renderAura(*frame, {}, source, 0.5); });
        std::printf("  from %-16s fog %.2f ms, aura %.2f ms\n", name, fogMs, auraMs);
        out[name] = {{"fogMs", fogMs}, {"auraMs", auraMs}};
    }
    return out;
}

nlohmann::json benchSmoothing(const BenchUpsampleOptions& options) {
    std::vector<frame::DepthData> depths;
    for (const frame::FramePtr& f : syntheticFrames(options, options.quick ? 12 : 40))
        depths.push_back(*f->sceneDepth);
    const processing::SmoothingParams params;
    const processing::TemporalNoise noise =
        processing::measureTemporalNoise(depths, params, options.quick ? 4 : 10);
    const int lagLarge = processing::measureStepLag(0.5f, params);
    const int lagSmall = processing::measureStepLag(params.jumpMeters / 2.0f, params);
    const double flicker = noise.rawFlicker / noise.smoothedFlicker,
                 spread = noise.rawSpread / noise.smoothedSpread;
    std::printf(
        "\ntemporal smoothing (alpha %.2f, jump %.2f m, holes %d frames) on the static synthetic scene, "
        "%zu steady pixels:\n  frame-to-frame flicker %.2f -> %.2f mm (%.2fx less; target >= 3x: %s)\n"
        "  per-pixel temporal spread %.2f -> %.2f mm (%.2fx less)\n"
        "  a moving depth step lags %d frame(s) (0.5 m step) and %d frame(s) (%.2f m step, below the "
        "jump threshold); target <= 2: %s\n",
        params.alpha, params.jumpMeters, params.holeFrames, noise.pixels, noise.rawFlicker * 1e3,
        noise.smoothedFlicker * 1e3, flicker, flicker >= 3.0 ? "met" : "MISSED", noise.rawSpread * 1e3,
        noise.smoothedSpread * 1e3, spread, lagLarge, lagSmall, params.jumpMeters / 2.0f,
        std::max(lagLarge, lagSmall) <= 2 ? "met" : "MISSED");
    return {{"alpha", params.alpha},
            {"flickerReduction", flicker},
            {"spreadReduction", spread},
            {"rawFlickerM", noise.rawFlicker},
            {"smoothedFlickerM", noise.smoothedFlicker},
            {"stepLagFrames", lagLarge},
            {"smallStepLagFrames", lagSmall}};
}

} // namespace dc::tool::upsample
