#pragma once

#include "base/expected.h"
#include "base/worker.h"
#include "engine/demand.h"
#include "exporting/export.h"
#include "frame/camera_model.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace dc::engine {

// The depth an export writes, processed as `demand` says (smoothing, upsampling, depth source) by a
// ProcessingGraph of its own, frame after frame in order: each written frame's sceneDepth is the depth
// the instrument would show for it. Null when the demand asks for no processing (frames as recorded).
std::function<frame::Frame(frame::Frame)> processedDepth(const Demand& demand);

// One replay of a fused export (`depthcloud export` given --source more than once), placed in the world as
// the window places a source: its spec's pose= after each frame's own pose (frame::worldPlacement).
struct FusedExportSource {
    std::string spec; // as given, which names it in the files' comments
    std::unique_ptr<devices::replay::ReplaySource> source;
    frame::RigidTransform placement; // the spec's pose=, the identity when it has none
    // Its own processing, as processedDepth makes it (a graph per source: each keeps its own state).
    std::function<frame::Frame(frame::Frame)> transform;
};

// Opens `spec` (anything openReplaySpecSource takes) for a fused export; an error says what is wrong.
Expected<FusedExportSource> openFusedExportSource(const std::string& spec);

// One PLY per frame of sources[0] in options.frames, holding every source's points in the world frame:
// that frame, and each further source's frame nearest it on their common clock (onCompanionClock, the frame
// the window shows beside it). A frame that any source cannot read is skipped with a warning. Only the PLY
// format; options.transform and options.worldCoordinates are not used (each source has its transform, and
// several sources are always in world coordinates).
Expected<exporting::ExportResult> exportFused(std::vector<FusedExportSource>& sources,
                                              const exporting::ExportOptions& options,
                                              const exporting::ExportProgress& progress = {});

// An export of a replay source's frame range running on its own thread, so the UI stays responsive; the
// UI polls progress() and may cancel(). It opens its own copy of the source (sources are not thread-safe)
// and calls exactly the code `depthcloud export` calls, so both write the same files.
class ExportJob {
public:
    static Expected<std::unique_ptr<ExportJob>> start(const std::string& replaySpec,
                                                      const exporting::ExportOptions& options);
    ~ExportJob();
    ExportJob(const ExportJob&) = delete;
    ExportJob& operator=(const ExportJob&) = delete;

    // Frames done and in total.
    std::pair<std::size_t, std::size_t> progress() const { return {done_.load(), total_.load()}; }
    void cancel() { cancelled_ = true; }
    bool finished() const { return finished_.load(); }
    // Once finished: what was written, or why it stopped.
    std::optional<Expected<exporting::ExportResult>> result() const;
    // Waits for the thread (the destructor cancels first).
    void join();

private:
    ExportJob() = default;

    std::atomic<std::size_t> done_{0};
    std::atomic<std::size_t> total_{0};
    std::atomic<bool> cancelled_{false};
    std::atomic<bool> finished_{false};
    mutable std::mutex mutex_;
    std::optional<Expected<exporting::ExportResult>> result_;
    base::Worker thread_;
};

} // namespace dc::engine
