// Benchmarks of the live capture path over the fake V4L2 driver (no kernel needed):
//   capture-thread CPU per frame for 1280x720 Z16 (+ 1280x720 YUYV) through the real UvcDevice and
//   V4l2Node (dequeue, Z16 -> meters, color copy, pairing, requeue), and the latency our code adds
//   between the driver's timestamp and a consumer taking the frame from the Session.
// Run: build-live/tests/unit/bench_live [--benchmark_repetitions=N]

#include "base/clock.h"
#include "devices/session.h"
#include "devices/uvc/uvc_device.h"
#include "tests/unit/live/fake_v4l2.h"

#include <benchmark/benchmark.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <filesystem>

namespace dc::devices {
namespace {

using v4l2::testing::FakeFrame;
using v4l2::testing::FakeV4l2;

constexpr int kW = 1280;
constexpr int kH = 720;
constexpr const char* kDepth = "/dev/video0";
constexpr const char* kColor = "/dev/video1";

// The buffer already holds the frame, as after the driver's DMA: the fake copies nothing.
FakeFrame inPlace(std::uint32_t bytes, std::int64_t timestampNs) {
    FakeFrame f;
    f.bytesused = bytes;
    f.timestampNs = timestampNs;
    return f;
}

UvcConfig configFor(bool color) {
    UvcConfig c;
    c.depthNode = kDepth;
    c.colorNode = color ? kColor : "";
    c.color = color;
    c.sysfsRoot = std::filesystem::temp_directory_path().string() + "/dc-no-sysfs";
    c.depthScaleMeters = 0.001f;
    return c;
}

void captureThread(benchmark::State& state, bool color) {
    FakeV4l2 fake;
    fake.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, kW, kH, {30}}}});
    fake.addNode(kColor, {.modes = {{V4L2_PIX_FMT_YUYV, kW, kH, {30}}}});
    UvcDevice device(configFor(color), fake);
    if (!device.open() || !device.start()) {
        state.SkipWithError("cannot start the device");
        return;
    }
    const std::uint32_t frameBytes = kW * kH * 2;
    std::int64_t t = 1'000'000'000;
    for (auto _ : state) {
        t += 33'333'333;
        fake.pushFrame(kDepth, inPlace(frameBytes, t));
        if (color)
            fake.pushFrame(kColor, inPlace(frameBytes, t + 1'000'000));
        CaptureResult r;
        while (r.kind != CaptureResult::Kind::Frame)
            r = device.capture(std::chrono::milliseconds(100));
        benchmark::DoNotOptimize(r.frame);
    }
}

void BM_CaptureThreadZ16(benchmark::State& state) {
    captureThread(state, false);
}
void BM_CaptureThreadZ16PlusYuyv(benchmark::State& state) {
    captureThread(state, true);
}
BENCHMARK(BM_CaptureThreadZ16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaptureThreadZ16PlusYuyv)->Unit(benchmark::kMillisecond);

// Driver timestamp -> consumer: the frame is stamped "now" as it is handed to the fake driver, the session's
// capture thread dequeues and converts it, and this thread takes it from the mailbox.
void BM_TimestampToConsumer(benchmark::State& state) {
    FakeV4l2 fake;
    fake.addNode(kDepth, {.modes = {{V4L2_PIX_FMT_Z16, kW, kH, {30}}}});
    Session session(std::make_unique<UvcDevice>(configFor(false), fake));
    if (!session.start()) {
        state.SkipWithError("cannot start the session");
        return;
    }
    std::vector<double> latencies;
    for (auto _ : state) {
        const std::int64_t stamp = base::monotonicNowNs();
        fake.pushFrame(kDepth, inPlace(kW * kH * 2, stamp));
        const auto frame = session.waitForFrame(std::chrono::seconds(2));
        if (!frame) {
            state.SkipWithError("no frame");
            break;
        }
        const double ms = frameAgeMs(**frame);
        latencies.push_back(ms);
        state.SetIterationTime(ms / 1000.0);
    }
    if (latencies.empty())
        return;
    std::sort(latencies.begin(), latencies.end());
    state.counters["p50_ms"] = latencies[latencies.size() / 2];
    state.counters["p99_ms"] = latencies[latencies.size() * 99 / 100];
}
BENCHMARK(BM_TimestampToConsumer)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(200);

} // namespace
} // namespace dc::devices

BENCHMARK_MAIN();
