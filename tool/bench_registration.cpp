#include "tool/bench_registration.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/synthetic/synthetic_device.h"
#include "processing/point_colours.h"
#include "processing/registration.h"
#include "tool/bench_median.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <vector>

namespace dc::tool {

namespace {

struct Case {
    const char* name;
    std::function<void()> work;
};

} // namespace

CLI::App* addBenchRegistrationCommand(CLI::App& bench, BenchRegistrationOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "registration", "two-sensor point colours and aligned depth: 848x480 depth into 1280x720");
    cmd->add_option("--runs", o.runs, "measured runs per case")
        ->check(CLI::Range(5, 10000))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

int runBenchRegistration(const BenchRegistrationOptions& o) {
    setLogQuiet(true);
    devices::SyntheticDevice device(devices::syntheticRigConfig());
    if (Status s = device.open(); !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    const frame::FramePtr frame = device.makeFrame(0, 0.0);
    const frame::Plane<float>& depth = frame->sceneDepth->depthMeters;
    frame::Frame oneCamera = *frame;
    oneCamera.rig = nullptr;
    processing::CameraColourTable table;
    const std::vector<Case> cases{
        {"registration",
         [&] {
             processing::registerDepth(depth, *frame->rig, frame->capturedImage.width,
                                       frame->capturedImage.height);
         }},
        {"registered colours", [&] { processing::framePointColours(*frame, depth, table); }},
        {"aligned depth",
         [&] {
             processing::alignDepthToColour(depth, *frame->rig, frame->capturedImage.width,
                                            frame->capturedImage.height);
         }},
        {"single-camera colours (baseline)",
         [&] { processing::framePointColours(oneCamera, depth, table); }}};
    std::printf("depthcloud bench registration --runs %d: %dx%d depth -> %dx%d colour, synthetic rig, median "
                "of %d runs\n",
                o.runs, depth.width, depth.height, frame->capturedImage.width, frame->capturedImage.height,
                o.runs);
    const int defaultThreads = cv::getNumThreads();
    nlohmann::json results = nlohmann::json::array();
    for (int threads : {1, 2}) {
        cv::setNumThreads(threads);
        nlohmann::json row{{"threads", threads}};
        for (const Case& c : cases) {
            const double ms = medianMs(o.runs, [&c](int) { c.work(); });
            std::printf("  %d thread(s)  %-34s %8.2f ms\n", threads, c.name, ms);
            row[c.name] = ms;
        }
        results.push_back(row);
    }
    cv::setNumThreads(defaultThreads);
    if (o.jsonPath.empty())
        return kExitOk;
    if (Status s = base::writeTextFile(o.jsonPath,
                                       nlohmann::json{{"runs", o.runs}, {"results", results}}.dump(2) + "\n");
        !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
