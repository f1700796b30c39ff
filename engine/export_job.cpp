#include "engine/export_job.h"

#include "base/barrier.h"
#include "base/log.h"
#include "devices/replay/replay_spec.h"
#include "engine/processing_graph.h"

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
