// depthcloud align: one depth frame from each of two sources, their overlap consistency through the
// transform their poses give, point-to-plane ICP from there, and B's refined placement, printed, as JSON and
// saved as extrinsics. The sources are opened directly (no Session, no GL), one after the other: the scene is
// taken to hold still meanwhile.
#include "tool/align_command.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/source_pose.h"
#include "devices/source_spec.h"
#include "exporting/ply.h"
#include "frame/multi_camera_extrinsics.h"
#include "processing/rigid_alignment.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace dc::tool {

namespace {

using json = nlohmann::json;

constexpr auto kAlignFrameWait = std::chrono::seconds(10);

// A source's first frame with depth, and where its spec placed it (the identity without pose=).
struct Taken {
    frame::FramePtr frame;
    frame::RigidTransform placement;
};

Expected<frame::FramePtr> firstDepthFrame(devices::Device& device) {
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < kAlignFrameWait) {
        devices::CaptureResult r = device.capture(std::chrono::milliseconds(500));
        if (r.kind == devices::CaptureResult::Kind::EndOfStream)
            return Error{"the source ended before its first depth frame"};
        if (r.kind == devices::CaptureResult::Kind::Disconnected ||
            r.kind == devices::CaptureResult::Kind::Error)
            return Error{"the source failed: " + r.message};
        if (r.kind == devices::CaptureResult::Kind::Frame && r.frame && r.frame->sceneDepth &&
            !r.frame->sceneDepth->depthMeters.empty())
            return std::move(r.frame);
    }
    return Error{"no depth frame from the source for 10 s"};
}

// An error prefixed "--source" is a bad argument; any other is the source failing.
Expected<Taken> takeFirstFrame(const std::string& spec) {
    auto placement = devices::sourcePlacement(spec);
    auto device = placement ? devices::openSourceSpec(spec)
                            : Expected<std::unique_ptr<devices::Device>>(placement.error());
    if (!device)
        return Error{"--source " + spec + ": " + device.error().message};
    if (Status s = (*device)->open(); !s)
        return Error{spec + ": " + s.error().message};
    if (Status s = (*device)->start(); !s)
        return Error{spec + ": " + s.error().message};
    auto frame = firstDepthFrame(**device);
    (void)(*device)->stop();
    (*device)->close();
    if (!frame)
        return Error{spec + ": " + frame.error().message};
    return Taken{std::move(*frame), placement->cameraToWorld.value_or(frame::RigidTransform{})};
}

json transformJson(const frame::RigidTransform& t) {
    const auto q = frame::quaternionFromRotation(t.rotation);
    const auto& p = t.translationMeters;
    return json::array({p[0], p[1], p[2], q[0], q[1], q[2], q[3]});
}

json overlapJson(const processing::OverlapFigure& f) {
    return {{"medianMm", f.medianMm}, {"overlapFraction", f.overlapFraction}, {"pairs", f.count}};
}

struct Alignment {
    processing::IcpResult icp;
    double icpMs = 0.0;
    frame::RigidTransform placementB; // B's refined placement: pose=FILE#camera_1 gives it back
    frame::RigidTransform aToWorld;
    frame::RigidTransform refinedBToWorld;
};

// B's refined camera-to-world keeps A where it is: A's pose after the refined A -> B, backwards. B's
// placement is what carries its own pose (none for a fixed camera) there: the world's correction, then the
// old placement.
Expected<Alignment> align(const Taken& a, const Taken& b) {
    if (a.frame->pose.has_value() != b.frame->pose.has_value())
        return Error{"one source has a pose and the other none: give both a pose= (or neither)"};
    const frame::Pose poseA = a.frame->pose.value_or(frame::Pose{});
    const frame::Pose poseB = b.frame->pose.value_or(frame::Pose{});
    const processing::DepthCloud cloudA{&*a.frame->sceneDepth, a.frame->depthIntrinsics()};
    const processing::DepthCloud cloudB{&*b.frame->sceneDepth, b.frame->depthIntrinsics()};
    const auto start = std::chrono::steady_clock::now();
    Alignment out;
    out.icp = processing::refineAlignment(cloudA, cloudB, processing::relativeTransform(poseA, poseB));
    out.icpMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (out.icp.status == processing::IcpStatus::InvalidInput ||
        out.icp.status == processing::IcpStatus::TooFewPoints)
        return Error{std::string("ICP: ") + processing::toString(out.icp.status) + " (" +
                     std::to_string(out.icp.before.count) + " overlapping samples)"};
    out.aToWorld = frame::rigidFromPose(poseA);
    out.refinedBToWorld = frame::compose(out.aToWorld, frame::inverse(out.icp.aToB));
    const frame::RigidTransform& refinedB = out.refinedBToWorld;
    const frame::RigidTransform worldCorrection =
        frame::compose(refinedB, frame::inverse(frame::rigidFromPose(poseB)));
    out.placementB = frame::compose(worldCorrection, b.placement);
    return out;
}

json alignmentJson(const Alignment& r, const Taken& a) {
    const processing::IcpResult& icp = r.icp;
    return {{"status", processing::toString(icp.status)},
            {"converged", icp.converged},
            {"iterations", icp.iterations},
            {"icpMs", r.icpMs},
            {"before", overlapJson(icp.before)},
            {"after", overlapJson(icp.after)},
            {"correctionDegrees", icp.correctionDegrees},
            {"correctionMm", icp.correctionMm},
            {"conditionRatio", icp.conditionRatio},
            {"placementA", transformJson(a.placement)},
            {"placementB", transformJson(r.placementB)}};
}

void printAlignment(const json& j) {
    const auto overlap = [](const json& f) {
        std::printf("median %.2f mm over %.0f %% of A's samples", f["medianMm"].get<double>(),
                    100.0 * f["overlapFraction"].get<double>());
    };
    std::printf("overlap before: ");
    overlap(j["before"]);
    std::printf("\nICP: %s, %s after %d iterations in %.0f ms; correction %.3f deg, %.1f mm\noverlap after: ",
                j["status"].get<std::string>().c_str(),
                j["converged"].get<bool>() ? "converged" : "not converged", j["iterations"].get<int>(),
                j["icpMs"].get<double>(), j["correctionDegrees"].get<double>(),
                j["correctionMm"].get<double>());
    overlap(j["after"]);
    std::string pose;
    for (const json& v : j["placementB"])
        pose += (pose.empty() ? "" : ",") + std::to_string(v.get<double>());
    std::printf("\nB's placement: pose=%s\n", pose.c_str());
}

Status saveExtrinsics(const AlignOptions& o, const Taken& a, const Alignment& r) {
    const frame::CameraExtrinsicsSet rig{{{"a", a.placement}, {"b", r.placementB}}, {}};
    const std::pair<const std::string*, frame::ExtrinsicsFormat> files[] = {
        {&o.savePath, frame::ExtrinsicsFormat::OpenCvYaml},
        {&o.kalibrPath, frame::ExtrinsicsFormat::KalibrCamchain}};
    for (const auto& [path, format] : files) {
        if (path->empty())
            continue;
        auto text = frame::writeCameraExtrinsics(rig, format);
        if (!text)
            return Error{*path + ": " + text.error().message};
        if (Status s = base::writeTextFile(*path, *text); !s)
            return Error{*path + ": " + s.error().message};
        std::printf("wrote %s\n", path->c_str());
    }
    return {};
}

// Every kept sample of `f` with its colour, moved into the world by `toWorld`.
void appendWorldPoints(const frame::Frame& f, const frame::RigidTransform& toWorld,
                       std::vector<processing::CloudPoint>& points) {
    for (processing::CloudPoint p : processing::buildPointCloud(f, frame::Confidence::Low, 0.0f)) {
        const auto w = toWorld.apply({p.x, p.y, p.z});
        p.x = static_cast<float>(w[0]);
        p.y = static_cast<float>(w[1]);
        p.z = static_cast<float>(w[2]);
        points.push_back(p);
    }
}

Status writeFusedCloud(const AlignOptions& o, const Taken& a, const Taken& b, const Alignment& r) {
    if (o.plyPath.empty())
        return {};
    std::vector<processing::CloudPoint> points;
    appendWorldPoints(*a.frame, r.aToWorld, points);
    const std::size_t fromA = points.size();
    appendWorldPoints(*b.frame, r.refinedBToWorld, points);
    const std::vector<std::string> comments{"depthcloud align: the world frame; A = " + o.sources[0] + ", " +
                                                std::to_string(fromA) + " points first",
                                            "B = " + o.sources[1] + " placed by ICP, " +
                                                std::to_string(points.size() - fromA) + " points after"};
    if (Status s = base::writeFileAtomically(o.plyPath, exporting::encodePly(points, comments)); !s)
        return Error{o.plyPath + ": " + s.error().message};
    std::printf("wrote %s\n", o.plyPath.c_str());
    return {};
}

std::string checkAlignArguments(const AlignOptions& o) {
    if (o.sources.size() != 2)
        return "--source: align takes two sources, A (the reference) then B (found " +
               std::to_string(o.sources.size()) + ")";
    std::error_code ec;
    for (const std::string* path : {&o.savePath, &o.kalibrPath, &o.jsonPath, &o.plyPath})
        if (!path->empty() && !o.overwrite && std::filesystem::exists(*path, ec))
            return *path + " already exists (pass --overwrite to replace it)";
    return {};
}

} // namespace

CLI::App* addAlignCommand(CLI::App& app, AlignOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "align",
        "how well two cameras' clouds agree where they overlap, and ICP refining B's placement against A");
    cmd->add_option("--source", o.sources,
                    "A (the reference), then B; each placed by its pose= or its own poses")
        ->required();
    cmd->add_option("--save", o.savePath,
                    "write both placements as OpenCV extrinsics (pose=FILE#camera_1 reads B's)");
    cmd->add_option("--save-kalibr", o.kalibrPath,
                    "write them as a Kalibr camchain (A must be at the origin)");
    cmd->add_option("--json", o.jsonPath, "also write every figure as JSON to this file");
    cmd->add_option("--ply", o.plyPath, "write both clouds fused in the world frame, B where ICP placed it");
    cmd->add_flag("--overwrite", o.overwrite, "replace the files if they exist");
    return cmd;
}

int runAlign(const AlignOptions& o) {
    setLogQuiet(true);
    if (std::string problem = checkAlignArguments(o); !problem.empty())
        return commandFailed("align", problem, kExitBadArguments);
    auto a = takeFirstFrame(o.sources[0]);
    auto b = a ? takeFirstFrame(o.sources[1]) : a;
    if (!a || !b) {
        const std::string& message = (!a ? a : b).error().message;
        return commandFailed("align", message,
                             message.rfind("--", 0) == 0 ? kExitBadArguments : kExitFailure);
    }
    auto aligned = align(*a, *b);
    if (!aligned)
        return commandFailed("align", aligned.error().message);
    const json j = alignmentJson(*aligned, *a);
    printAlignment(j);
    if (!o.jsonPath.empty())
        if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s)
            return commandFailed("align", "--json " + o.jsonPath + ": " + s.error().message);
    if (Status s = saveExtrinsics(o, *a, *aligned); !s)
        return commandFailed("align", s.error().message);
    if (Status s = writeFusedCloud(o, *a, *b, *aligned); !s)
        return commandFailed("align", s.error().message);
    return kExitOk;
}

} // namespace dc::tool
