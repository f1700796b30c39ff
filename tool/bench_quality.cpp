#include "tool/bench_quality.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/synthetic/synthetic_scene.h"
#include "processing/depth_quality.h"
#include "processing/edge_alignment.h"
#include "processing/registration.h"
#include "tool/bench_frames.h"
#include "tool/bench_median.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <vector>

namespace dc::tool {

namespace {

constexpr int kDepthWidth = 1280;
constexpr int kDepthHeight = 720;
constexpr int kQualityDistinctFrames = 8;
constexpr int kNoiseWindowFrames = 30;

// What the figures are made for: the synthetic camera's flat target (synthetic:plane=1.5,10,1), a wall
// 1.5 m away turned 10 degrees about the vertical axis with 1 mm of depth noise, in `count` distinct frames.
std::vector<frame::DepthData> flatTarget(const frame::Intrinsics& k, int count) {
    std::vector<frame::DepthData> frames;
    for (int i = 0; i < count; ++i)
        frames.push_back(
            devices::flatTargetDepth(k, {1.5, 10.0, 1.0}, true, 1, static_cast<std::uint64_t>(i)));
    return frames;
}

std::vector<processing::Point3d> roiPoints(const frame::DepthData& depth, const frame::Intrinsics& k,
                                           const processing::QualityParams& params) {
    processing::FillBreakdown counts;
    const auto causes = processing::classifySamples(depth, params, counts);
    std::vector<processing::Point3d> points;
    const processing::Roi& r = params.roi;
    for (std::size_t i = 0; i < causes.size(); ++i) {
        if (causes[i] != processing::SampleCause::Valid)
            continue;
        const int x = r.x + static_cast<int>(i % static_cast<std::size_t>(r.width));
        const int y = r.y + static_cast<int>(i / static_cast<std::size_t>(r.width));
        const double z = depth.depthMeters.at(x, y);
        points.push_back({(x - k.cx) * z / k.fx, (y - k.cy) * z / k.fy, z});
    }
    return points;
}

struct Part {
    const char* name;
    std::function<void(int)> work;
};

nlohmann::json runCase(const char* scene, const std::vector<frame::DepthData>& frames,
                       const frame::Intrinsics& k, double roiPercent, int runs) {
    const frame::DepthData& first = frames.front();
    processing::QualityParams params;
    params.roi = processing::centredRoi(first.depthMeters.width, first.depthMeters.height, roiPercent);
    const auto depthOf = [&](int i) -> const frame::DepthData& { return frames[i % frames.size()]; };
    const std::vector<processing::Point3d> points = roiPoints(first, k, params);
    processing::NoiseWindow window(params, kNoiseWindowFrames);
    const std::vector<Part> parts{
        {"every per-frame figure (fill, causes, robust and DQT fits, noise window, its median)",
         [&](int i) {
             const auto q = processing::measureFrameQuality(depthOf(i), k, params);
             window.add(depthOf(i),
                        q ? std::span<const processing::SampleCause>(q->causes)
                          : std::span<const processing::SampleCause>(),
                        q && q->plane ? std::optional(q->plane->planeFitRmsMm) : std::nullopt);
             // The Quality panel reads the temporal noise of every frame (engine/processing_graph.cpp).
             static_cast<void>(window.temporalNoiseMm());
         }},
        {"the per-frame figures (fill, causes, robust and DQT fits), without the window's",
         [&](int i) { static_cast<void>(processing::measureFrameQuality(depthOf(i), k, params)); }},
        {"fill rate and its causes",
         [&](int i) {
             processing::FillBreakdown counts;
             processing::classifySamples(depthOf(i), params, counts);
         }},
        {"robust plane fit", [&](int) { processing::fitPlaneRobust(points); }},
        {"noise window (one frame in, one out)",
         [&](int i) {
             processing::FillBreakdown counts;
             window.add(depthOf(i), processing::classifySamples(depthOf(i), params, counts), 1.0);
         }},
        {"temporal noise, the median over the window's pixels",
         [&](int) { static_cast<void>(window.temporalNoiseMm()); }},
        {"DQT's plain fit and trimmed RMS (baseline)", [&](int) { processing::dqtPlaneFitRms(points); }}};
    std::printf("%s, %dx%d depth, ROI %d%% (%dx%d, %zu valid samples), median of %d frames:\n", scene,
                first.depthMeters.width, first.depthMeters.height, static_cast<int>(roiPercent),
                params.roi.width, params.roi.height, points.size(), runs);
    nlohmann::json row{{"scene", scene},
                       {"roiPercent", roiPercent},
                       {"roiSamples", params.roi.width * params.roi.height},
                       {"validSamples", points.size()}};
    for (const Part& p : parts) {
        const double ms = medianMs(runs, p.work, 3);
        std::printf("  %-84s %8.2f ms\n", p.name, ms);
        row[p.name] = ms;
    }
    return row;
}

// The Quality panel's colour-to-depth alignment, off by default because it registers the colour every
// frame: its cost on frames with a camera image, the registration and the edge comparison apart.
nlohmann::json runAlignmentCase(const char* scene, const std::vector<frame::FramePtr>& frames,
                                double roiPercent, int runs) {
    const frame::Plane<float>& first = frames.front()->sceneDepth->depthMeters;
    const processing::Roi roi = processing::centredRoi(first.width, first.height, roiPercent);
    processing::CameraColourTable table;
    const auto frameOf = [&](int i) -> const frame::Frame& { return *frames[i % frames.size()]; };
    const auto registered = [&](int i) {
        const frame::Plane<float>& depth = frameOf(i).sceneDepth->depthMeters;
        return processing::colourAlignedToDepth(frameOf(i), depth, depth.width, depth.height, table);
    };
    const processing::RgbImage colour = registered(0);
    const double whole = medianMs(runs, [&](int i) {
        static_cast<void>(processing::measureEdgeAlignment(frameOf(i).sceneDepth->depthMeters, registered(i),
                                                           frameOf(i).depthIntrinsics(), roi));
    });
    const double registration = medianMs(runs, [&](int i) { static_cast<void>(registered(i)); });
    const double edges = medianMs(runs, [&](int) {
        static_cast<void>(
            processing::measureEdgeAlignment(first, colour, frames.front()->depthIntrinsics(), roi));
    });
    std::printf("%s, %dx%d depth, ROI %d%%, colour-to-depth alignment, median of %d frames:\n", scene,
                first.width, first.height, static_cast<int>(roiPercent), runs);
    std::printf("  %-84s %8.2f ms\n", "registration and edge comparison", whole);
    std::printf("  %-84s %8.2f ms\n", "the colour registered onto the depth", registration);
    std::printf("  %-84s %8.2f ms\n", "the edges compared", edges);
    return {{"scene", scene},
            {"roiPercent", roiPercent},
            {"alignment", whole},
            {"alignmentRegistration", registration},
            {"alignmentEdges", edges}};
}

} // namespace

CLI::App* addBenchQualityCommand(CLI::App& bench, BenchQualityOptions& o) {
    CLI::App* cmd = bench.add_subcommand(
        "quality", "cost per frame of the depth-quality figures on 1280x720 depth, DQT's plain fit beside");
    cmd->add_option("--frames", o.frames, "measured frames per case")
        ->check(CLI::Range(5, 100000))
        ->capture_default_str();
    cmd->add_option("--json", o.jsonPath, "also write the results as JSON to this file");
    return cmd;
}

int runBenchQuality(const BenchQualityOptions& o) {
    setLogQuiet(true);
    devices::SyntheticConfig config;
    config.depthWidth = kDepthWidth;
    config.depthHeight = kDepthHeight;
    const std::vector<frame::FramePtr> sceneFrames = syntheticFrames(config, kQualityDistinctFrames);
    if (sceneFrames.empty() || !sceneFrames.front()->sceneDepth) {
        std::fprintf(stderr, "depthcloud: error: cannot make synthetic frames\n");
        return kExitFailure;
    }
    const frame::Intrinsics k = sceneFrames.front()->depthIntrinsics();
    std::vector<frame::DepthData> scene;
    for (const frame::FramePtr& f : sceneFrames)
        scene.push_back(*f->sceneDepth);
    const std::vector<frame::DepthData> flat = flatTarget(k, kQualityDistinctFrames);
    std::printf("depthcloud bench quality --frames %d: %d distinct frames of each scene\n", o.frames,
                kQualityDistinctFrames);
    nlohmann::json results = nlohmann::json::array();
    results.push_back(runCase("flat target", flat, k, 40.0, o.frames));
    results.push_back(runCase("flat target", flat, k, 100.0, o.frames));
    results.push_back(runCase("synthetic scene (cluttered)", scene, k, 40.0, o.frames));
    results.push_back(runAlignmentCase("synthetic scene (cluttered)", sceneFrames, 40.0, o.frames));
    const std::vector<frame::FramePtr> rigFrames =
        syntheticFrames(devices::syntheticRigConfig(), kQualityDistinctFrames);
    if (!rigFrames.empty() && rigFrames.front()->sceneDepth)
        results.push_back(
            runAlignmentCase("synthetic rig (848x480 depth, 1280x720 colour)", rigFrames, 40.0, o.frames));
    if (o.jsonPath.empty())
        return kExitOk;
    if (Status s = base::writeTextFile(
            o.jsonPath, nlohmann::json{{"frames", o.frames}, {"cases", results}}.dump(2) + "\n");
        !s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace dc::tool
