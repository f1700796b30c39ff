#pragma once

#include "base/expected.h"
#include "base/worker.h"
#include "engine/demand.h"
#include "exporting/export.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace dc::engine {

// The depth an export writes, processed as `demand` says (smoothing, upsampling, depth source) by a
// ProcessingGraph of its own, frame after frame in order: each written frame's sceneDepth is the depth
// the instrument would show for it. Null when the demand asks for no processing (frames as recorded).
std::function<frame::Frame(frame::Frame)> processedDepth(const Demand& demand);

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
