#include "base/clock.h"
#include "base/files.h"
#include "base/rolling_stats.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "frame/frame.h"
#include "frame/image_io.h"
#include "processing/confidence_estimator.h"
#include "tool/live_commands.h"
#include "tool/options.h"

#include <linux/videodev2.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <vector>

namespace dc::tool {

namespace {

constexpr int kCaptureWarmupFrames = 10;

// A Z16 frame as a sensor sends it: a slanted plane in millimeters with a few holes (0 = no measurement).
std::vector<std::uint8_t> z16Frame(int w, int h, int frame) {
    std::vector<std::uint8_t> raw(static_cast<std::size_t>(w) * h * 2);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool hole = (x * 7 + y * 13 + frame) % 97 == 0;
            const auto mm = static_cast<std::uint16_t>(hole ? 0 : 800 + x / 4 + y / 8 + frame);
            const std::size_t i = 2 * (static_cast<std::size_t>(y) * w + x);
            raw[i] = static_cast<std::uint8_t>(mm & 0xff);
            raw[i + 1] = static_cast<std::uint8_t>(mm >> 8);
        }
    return raw;
}

std::vector<std::uint8_t> yuyvFrame(int w, int h) {
    std::vector<std::uint8_t> raw(static_cast<std::size_t>(w) * h * 2);
    for (std::size_t i = 0; i < raw.size(); ++i)
        raw[i] = static_cast<std::uint8_t>(i % 2 == 0 ? (i / 2) % 220 + 16 : 128);
    return raw;
}

struct Medians {
    double depthMs = 0;
    double colorMs = 0;
    double frameMs = 0;
    double totalMs = 0;
    double estimateMs = 0;
};

} // namespace

CLI::App* addBenchCaptureCommand(CLI::App& bench, BenchCaptureOptions& o) {
    CLI::App* cmd =
        bench.add_subcommand("capture", "CPU time per frame of the live capture thread's conversions");
    cmd->add_option("--frames", o.frames, "measured frames")
        ->check(CLI::Range(10, 100000))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

int runBenchCapture(const BenchCaptureOptions& o) {
    const int w = o.width;
    const int h = o.height;
    const std::vector<std::uint8_t> z16[2] = {z16Frame(w, h, 0), z16Frame(w, h, 1)};
    const std::vector<std::uint8_t> yuyv = yuyvFrame(w, h);
    const auto bpl = static_cast<std::uint32_t>(2 * w);
    base::RollingStats depthMs(static_cast<std::size_t>(o.frames)),
        colorMs(static_cast<std::size_t>(o.frames)), frameMs(static_cast<std::size_t>(o.frames)),
        totalMs(static_cast<std::size_t>(o.frames)), estimateMs(static_cast<std::size_t>(o.frames));
    std::uint64_t checksum = 0;
    frame::FramePtr last;
    for (int i = 0; i < kCaptureWarmupFrames + o.frames; ++i) {
        // Exactly the capture thread's work per depth+color pair (UvcDevice::takeBuffer, makeFrame).
        const double t0 = base::threadCpuMs();
        frame::Plane<float> meters;
        devices::v4l2::depthToMeters(z16[i % 2], w, h, bpl, 0.001f, meters);
        const double t1 = base::threadCpuMs();
        auto image = devices::v4l2::toCapturedImage(V4L2_PIX_FMT_YUYV, yuyv, w, h, bpl);
        const double t2 = base::threadCpuMs();
        auto frame = std::make_shared<frame::Frame>();
        frame->capturedImage = image ? std::move(*image) : frame::CapturedImage{};
        frame->sceneDepth = frame::DepthData{std::move(meters), {}};
        last = frame;
        const double t3 = base::threadCpuMs();
        if (i < kCaptureWarmupFrames)
            continue;
        depthMs.add(t1 - t0);
        colorMs.add(t2 - t1);
        frameMs.add(t3 - t2);
        totalMs.add(t3 - t0);
    }
    // Separately, as it runs on the render thread: the confidence estimate such a camera gets.
    processing::ConfidenceEstimatorStage estimator;
    for (int i = 0; i < kCaptureWarmupFrames + o.frames; ++i) {
        const double t0 = base::threadCpuMs();
        const frame::FramePtr estimated = estimator.process(last, {});
        const double t1 = base::threadCpuMs();
        checksum += estimated->sceneDepth->confidence
                        .pixels[static_cast<std::size_t>(i) % (static_cast<std::size_t>(w) * h)];
        if (i >= kCaptureWarmupFrames)
            estimateMs.add(t1 - t0);
    }
    const Medians m{depthMs.median(), colorMs.median(), frameMs.median(), totalMs.median(),
                    estimateMs.median()};
    std::printf("capture thread, %dx%d Z16 + %dx%d YUYV, median CPU ms per frame over %d frames:\n", w, h, w,
                h, o.frames);
    std::printf("  Z16 -> meters %.3f | YUYV copy %.3f | frame assembly %.3f | total %.3f (%.1f%% of a core "
                "at 30 fps)\n",
                m.depthMs, m.colorMs, m.frameMs, m.totalMs, m.totalMs / (1000.0 / 30.0) * 100.0);
    std::printf("render thread, confidence estimate %dx%d: %.3f ms  (checksum %llu)\n", w, h, m.estimateMs,
                static_cast<unsigned long long>(checksum));
    if (!o.jsonPath.empty()) {
        const nlohmann::json j{{"width", w},
                               {"height", h},
                               {"frames", o.frames},
                               {"z16ToMetersMs", m.depthMs},
                               {"yuyvCopyMs", m.colorMs},
                               {"frameAssemblyMs", m.frameMs},
                               {"captureTotalMs", m.totalMs},
                               {"confidenceEstimateMs", m.estimateMs}};
        if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s) {
            std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
            return kExitFailure;
        }
    }
    return kExitOk;
}

} // namespace dc::tool
