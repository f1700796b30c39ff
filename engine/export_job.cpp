#include "engine/export_job.h"

#include "base/barrier.h"
#include "base/log.h"
#include "devices/replay/replay_device.h"
#include "devices/replay/replay_spec.h"
#include "devices/source_pose.h"
#include "engine/processing_graph.h"
#include "engine/replay_follow.h"
#include "frame/world_placement.h"

#include <filesystem>
#include <limits>

namespace dc::engine {

std::function<frame::Frame(frame::Frame)> processedDepth(const Demand& demand) {
    const processing::ProcessingSettings& p = demand.processing;
    const bool smoothed = p.smoothing && p.depthSource == processing::DepthSource::Smoothed;
    if (!smoothed && !p.upsampling)
        return {};
    Demand depthOnly;
    depthOnly.processing = p;
    depthOnly.pointColours = false;
    depthOnly.depthImage = false;
    depthOnly.confidencePanel = true; // exports carry confidence: estimate it where the source has none
    auto graph = std::make_shared<ProcessingGraph>();
    return [graph, depthOnly](frame::Frame frame) {
        auto in = std::make_shared<const frame::Frame>(std::move(frame));
        const processing::ShownFramePtr shown = graph->run(in, depthOnly, 1, true);
        frame::Frame out = *in;
        out.smoothedSceneDepth.reset();
        if (shown->depth.data)
            out.sceneDepth = *shown->depth.data;
        return out;
    };
}

namespace {

// A further source of a fused export as the export walks the first: its clock, and the frame it loaded
// last (a slower source pairs one frame with several of the first's).
struct FusedPartner {
    FusedExportSource* source = nullptr;
    RecordingSpan span;
    std::vector<std::int64_t> timestampsNs;
    std::size_t loaded = std::numeric_limits<std::size_t>::max();
    Expected<frame::Frame> frame = Error{"no frame loaded"};
};

std::vector<std::int64_t> timestampsOf(const devices::replay::ReplaySource& source) {
    std::vector<std::int64_t> timestamps(source.frameCount());
    for (std::size_t i = 0; i < timestamps.size(); ++i)
        timestamps[i] = source.timestampNs(i);
    return timestamps;
}

// Frame `i` of `s`, processed; an error names the source and the frame.
Expected<frame::Frame> processedFrame(FusedExportSource& s, std::size_t i) {
    auto frame = devices::replay::loadFrame(*s.source, i);
    if (frame && s.transform)
        *frame = s.transform(std::move(*frame));
    if (frame && !frame->sceneDepth)
        frame = Error{"it has no depth"};
    if (!frame)
        return Error{"frame " + std::to_string(i) + " of " + s.spec + ": " + frame.error().message};
    return frame;
}

// Each partner's frame nearest `timestampNs` of the first source, loaded when it is not the one loaded
// last; appended to `parts`, or the error of the first that cannot be read.
Status pairPartners(std::vector<FusedPartner>& partners, const RecordingSpan& first, std::int64_t timestampNs,
                    std::vector<exporting::PlacedFrame>& parts) {
    for (FusedPartner& p : partners) {
        const std::size_t nearest =
            devices::replay::nearestTimeIndex(p.timestampsNs, onCompanionClock(first, timestampNs, p.span));
        if (nearest != p.loaded) {
            p.frame = processedFrame(*p.source, nearest);
            p.loaded = nearest;
        }
        if (!p.frame)
            return p.frame.error();
        parts.push_back(
            {&*p.frame, nearest, frame::worldPlacement(*p.frame, p.source->placement), p.source->spec});
    }
    return {};
}

// The partners of sources[0]; an error when one holds no frames.
Expected<std::vector<FusedPartner>> partnersOf(std::vector<FusedExportSource>& sources) {
    std::vector<FusedPartner> partners;
    for (std::size_t i = 1; i < sources.size(); ++i) {
        FusedExportSource& s = sources[i];
        if (s.source->frameCount() == 0)
            return Error{s.spec + " holds no frames"};
        s.source->setDecodeColor(true);
        std::vector<std::int64_t> timestamps = timestampsOf(*s.source);
        const RecordingSpan span{timestamps.front(), timestamps.back()};
        partners.push_back({&s, span, std::move(timestamps)});
    }
    return partners;
}

} // namespace

Expected<FusedExportSource> openFusedExportSource(const std::string& spec) {
    auto placement = devices::sourcePlacement(spec);
    if (!placement)
        return placement.error();
    auto source = devices::replay::openReplaySpecSource(spec);
    if (!source)
        return source.error();
    return FusedExportSource{
        spec, std::move(*source), placement->cameraToWorld.value_or(frame::RigidTransform{}), {}};
}

Expected<exporting::ExportResult> exportFused(std::vector<FusedExportSource>& sources,
                                              const exporting::ExportOptions& options,
                                              const exporting::ExportProgress& progress) {
    if (sources.empty())
        return Error{"a fused export needs a source"};
    FusedExportSource& first = sources.front();
    const auto range = exporting::framesWithin(options.frames, first.source->frameCount());
    if (!range)
        return range.error();
    auto partners = partnersOf(sources);
    if (!partners)
        return partners.error();
    std::error_code ec;
    std::filesystem::create_directories(options.outDirectory, ec);
    if (ec)
        return Error{"cannot create " + options.outDirectory + ": " + ec.message()};
    first.source->setDecodeColor(true);
    const RecordingSpan firstSpan{first.source->timestampNs(0),
                                  first.source->timestampNs(first.source->frameCount() - 1)};
    exporting::ExportResult result;
    for (std::size_t i = range->first; i < range->end; ++i) {
        auto frame = processedFrame(first, i);
        std::vector<exporting::PlacedFrame> parts;
        if (frame)
            parts.push_back({&*frame, i, frame::worldPlacement(*frame, first.placement), first.spec});
        const Status paired = frame ? pairPartners(*partners, firstSpan, first.source->timestampNs(i), parts)
                                    : Status{frame.error()};
        if (!paired) {
            logWarning("export: skipping frame " + std::to_string(i) + ": " + paired.error().message);
            ++result.framesSkipped;
        } else if (Status s = exporting::writeFusedPly(parts, options.outDirectory); !s) {
            return s.error();
        } else {
            ++result.framesWritten;
        }
        if (progress && !progress(i - range->first + 1, range->end - range->first))
            return Error{"export cancelled after " + std::to_string(result.framesWritten) + " frames"};
    }
    return result;
}

Expected<std::unique_ptr<ExportJob>> ExportJob::start(const std::string& replaySpec,
                                                      const exporting::ExportOptions& options) {
    auto source = devices::replay::openReplaySpecSource(replaySpec);
    if (!source)
        return source.error();
    std::unique_ptr<ExportJob> job(new ExportJob());
    ExportJob* self = job.get();
    // The thread owns the source; errors and cancellation come back as values, never as exceptions.
    job->thread_ = base::Worker("export", [self, options, src = std::shared_ptr(std::move(*source))] {
        Expected<exporting::ExportResult> r = Error{"export did not run"};
        const Status ran = base::guarded("export failed", [&] {
            r = exporting::exportFrames(*src, options, [self](std::size_t done, std::size_t total) {
                self->done_ = done;
                self->total_ = total;
                return !self->cancelled_.load();
            });
        });
        if (!ran)
            r = ran.error();
        if (r)
            logNotice("exported " + std::to_string(r->framesWritten) + " frames to " + options.outDirectory);
        else
            logError("export to " + options.outDirectory + ": " + r.error().message);
        std::lock_guard lock(self->mutex_);
        self->result_ = std::move(r);
        self->finished_ = true;
    });
    return job;
}

ExportJob::~ExportJob() {
    cancel();
    join();
}

void ExportJob::join() {
    thread_.join();
}

std::optional<Expected<exporting::ExportResult>> ExportJob::result() const {
    std::lock_guard lock(mutex_);
    return result_;
}

} // namespace dc::engine
