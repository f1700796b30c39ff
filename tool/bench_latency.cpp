#include "base/files.h"
#include "devices/frame_age.h"
#include "devices/session.h"
#include "devices/source_spec.h"
#include "tool/live_commands.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace dc::tool {

namespace {

using namespace std::chrono_literals;

constexpr int kLatencyWarmupFrames = 10; // the first frames include connecting and subscribing
constexpr auto kFirstFrameWait = 10s;    // a source that delivers nothing in this long is a failure

double percentile(std::vector<double> values, double p) {
    std::sort(values.begin(), values.end());
    const auto at = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1) + 0.5);
    return values[std::min(at, values.size() - 1)];
}

} // namespace

CLI::App* addBenchLatencyCommand(CLI::App& bench, BenchLatencyOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "latency", "age of a live source's frames when a consumer takes them (ros: publish -> delivered)");
    cmd->add_option("--source", o.source,
                    "a ros: source (stamped with the publisher's clock) or a live camera")
        ->required();
    cmd->add_option("--seconds", o.seconds, "how long to measure")
        ->check(CLI::Range(1.0, 3600.0))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

// Frame stamps of ros: sources are the publisher's wall clock (ROS time), those of live cameras
// CLOCK_MONOTONIC: on the loopback, publisher and consumer share the machine's clocks.
int runBenchLatency(const BenchLatencyOptions& o) {
    auto device = devices::openSourceSpec(o.source);
    if (!device)
        return commandFailed("bench latency", "--source: " + device.error().message, kExitBadArguments);
    const devices::Capabilities capabilities = (*device)->capabilities();
    if (!devices::nowOnFrameClockNs(capabilities))
        return commandFailed("bench latency",
                             "--source: " + o.source + " is not live: its frames carry no capture time",
                             kExitBadArguments);
    devices::Session session(std::move(*device));
    if (Status s = session.start(); !s)
        return commandFailed("bench latency", s.error().message);
    std::vector<double> agesMs;
    int seen = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.seconds);
    while (std::chrono::steady_clock::now() < end) {
        auto frame = session.waitForFrame(seen == 0 ? std::chrono::milliseconds(kFirstFrameWait) : 1000ms);
        const std::int64_t now = *devices::nowOnFrameClockNs(capabilities);
        if (!frame && seen == 0)
            return commandFailed("bench latency", session.description() + " delivered no frame in " +
                                                      std::to_string(kFirstFrameWait.count()) + " s");
        if (frame && ++seen > kLatencyWarmupFrames)
            agesMs.push_back(devices::frameAgeMs(**frame, now));
    }
    const devices::SessionStats stats = session.stats();
    session.stop();
    if (agesMs.empty())
        return commandFailed("bench latency",
                             "no frame after the first " + std::to_string(kLatencyWarmupFrames));
    const double median = percentile(agesMs, 0.5), p99 = percentile(agesMs, 0.99),
                 worst = percentile(agesMs, 1.0);
    std::printf("%s: %zu frames, %s -> delivered: median %.2f ms, p99 %.2f ms, max %.2f ms; %llu dropped\n",
                session.description().c_str(), agesMs.size(),
                capabilities.realtimeTimestamps ? "publish" : "capture", median, p99, worst,
                static_cast<unsigned long long>(stats.framesDropped));
    if (!o.jsonPath.empty()) {
        const nlohmann::json j{{"source", o.source}, {"frames", agesMs.size()},
                               {"medianMs", median}, {"p99Ms", p99},
                               {"maxMs", worst},     {"dropped", stats.framesDropped}};
        if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s)
            return commandFailed("bench latency", s.error().message);
    }
    return kExitOk;
}

} // namespace dc::tool
