// depthcloud export: a recording or capture to PLY clouds, the Stray layout, 16-bit depth PNGs or MCAP;
// several recordings to PLY clouds fused in the world frame.

#include "base/log.h"
#include "devices/replay/replay_spec.h"
#include "devices/video/video_codec.h"
#include "engine/export_job.h"
#include "exporting/export.h"
#include "tool/options.h"
#include "tool/recording_commands.h"

#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dc::tool {

namespace {

// A one-line progress bar on stderr, redrawn when the percentage changes.
class ProgressBar {
public:
    bool update(std::size_t done, std::size_t total) {
        const int percent = static_cast<int>(100 * done / std::max<std::size_t>(total, 1));
        if (percent == lastPercent_)
            return true;
        lastPercent_ = percent;
        constexpr int kWidth = 40;
        const int filled = percent * kWidth / 100;
        std::fprintf(stderr, "\rexport [%.*s%*s] %3d%% %zu/%zu frames", filled,
                     "########################################", kWidth - filled, "", percent, done, total);
        if (done == total)
            std::fprintf(stderr, "\n");
        return true;
    }

private:
    int lastPercent_ = -1;
};

// The export's processing for `--upsample`: the instrument's upsampling stage with that method, on the
// sensor's depth; no transform for "none". Method names are checked by the parser.
std::function<frame::Frame(frame::Frame)> upsamplingOf(const std::string& name) {
    if (name == "none")
        return {};
    engine::Demand demand;
    demand.processing.upsampling = true;
    demand.processing.depthSource = processing::DepthSource::Raw;
    demand.processing.upsamplingParams.method = name == "full"      ? processing::UpsamplingMethod::Full
                                                : name == "global"  ? processing::UpsamplingMethod::Global
                                                : name == "quality" ? processing::UpsamplingMethod::Quality
                                                                    : processing::UpsamplingMethod::Fast;
    return engine::processedDepth(demand);
}

exporting::ExportFormat formatOf(const std::string& name) {
    if (name == "stray")
        return exporting::ExportFormat::Stray;
    if (name == "png16")
        return exporting::ExportFormat::Png16;
    if (name == "mcap")
        return exporting::ExportFormat::Mcap;
    return exporting::ExportFormat::Ply;
}

// An MCAP destination that is a directory, or a file that --overwrite does not allow replacing.
std::string mcapDestinationProblem(const ExportOptionsCli& o) {
    std::error_code ec;
    if (std::filesystem::is_directory(o.out, ec))
        return o.out + " is a directory (mcap writes one file)";
    if (!o.overwrite && std::filesystem::exists(o.out, ec))
        return o.out + " already exists (pass --overwrite to replace it)";
    return {};
}

// The export's --source that cannot be opened, as the viewer reports one: a bad argument, unless this
// build lacks the video support it needs.
int sourceCannotOpen(const Error& error) {
    return commandFailed("export", "--source: " + error.message,
                         devices::video::isVideoSupportMissing(error) ? kExitFailure : kExitBadArguments);
}

// --frames against a first source of `count` frames, into `options`; an exit code when it is wrong.
std::optional<int> applyFrames(const ExportOptionsCli& o, std::size_t count,
                               exporting::ExportOptions& options) {
    if (o.frames.empty())
        return std::nullopt;
    auto range = exporting::parseFrameRange(o.frames, count);
    if (!range)
        return commandFailed("export", "--frames: " + range.error().message, kExitBadArguments);
    options.frames = *range;
    return std::nullopt;
}

void printSummary(const ExportOptionsCli& o, const exporting::ExportOptions& options,
                  const exporting::ExportResult& result) {
    const std::string upsampled = o.upsample == "none" ? "" : ", depth upsampled (" + o.upsample + ")";
    const std::string fused =
        o.sources.size() > 1 ? ", " + std::to_string(o.sources.size()) + " sources fused in the world frame"
                             : "";
    const std::string skipped =
        result.framesSkipped ? " (" + std::to_string(result.framesSkipped) + " unreadable frames skipped)"
                             : "";
    std::printf("depthcloud export: wrote %zu frames as %s%s%s to %s%s\n", result.framesWritten,
                exporting::toString(options.format), upsampled.c_str(), fused.c_str(), o.out.c_str(),
                skipped.c_str());
}

// Several --source: one PLY per frame of the first with every source's points in the world frame.
int runFusedExport(const ExportOptionsCli& o) {
    if (o.format != "ply")
        return commandFailed("export",
                             "--format " + o.format + ": several --source are fused into PLY clouds only",
                             kExitBadArguments);
    std::vector<engine::FusedExportSource> sources;
    for (const std::string& spec : o.sources) {
        auto source = engine::openFusedExportSource(spec);
        if (!source)
            return sourceCannotOpen(sources.empty() ? source.error()
                                                    : Error{spec + ": " + source.error().message});
        source->transform = upsamplingOf(o.upsample);
        sources.push_back(std::move(*source));
    }
    exporting::ExportOptions options;
    options.outDirectory = o.out;
    if (auto failed = applyFrames(o, sources.front().source->frameCount(), options))
        return *failed;
    ProgressBar bar;
    auto result = engine::exportFused(
        sources, options, [&bar](std::size_t done, std::size_t total) { return bar.update(done, total); });
    if (!result)
        return commandFailed("export", result.error().message, kExitFailure);
    printSummary(o, options, *result);
    return kExitOk;
}

} // namespace

int runExport(const ExportOptionsCli& o) {
    setLogQuiet(true);
    if (o.sources.size() > 1)
        return runFusedExport(o);
    if (o.format == "mcap")
        if (const std::string problem = mcapDestinationProblem(o); !problem.empty())
            return commandFailed("export", "--out: " + problem, kExitBadArguments);
    auto source = devices::replay::openReplaySpecSource(o.sources.front());
    if (!source)
        return sourceCannotOpen(source.error());
    exporting::ExportOptions options;
    options.format = formatOf(o.format);
    options.outDirectory = o.out;
    options.worldCoordinates = o.world;
    options.overwrite = o.overwrite;
    options.transform = upsamplingOf(o.upsample);
    if (auto failed = applyFrames(o, (*source)->frameCount(), options))
        return *failed;
    ProgressBar bar;
    auto result = exporting::exportFrames(
        **source, options, [&bar](std::size_t done, std::size_t total) { return bar.update(done, total); });
    if (!result)
        return commandFailed("export", result.error().message, kExitFailure);
    printSummary(o, options, *result);
    return kExitOk;
}

} // namespace dc::tool
