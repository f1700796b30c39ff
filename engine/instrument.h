#pragma once

#include "base/rate_meter.h"
#include "base/rolling_stats.h"
#include "devices/recording/session_recording.h"
#include "devices/replay/replay_device.h"
#include "devices/session.h"
#include "engine/demand.h"
#include "engine/export_job.h"
#include "engine/frame_processor.h"
#include "engine/stage_stats.h"
#include "engine/timing_model.h"
#include "processing/accumulation_worker.h"

#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>

namespace dc::engine {

// Frames through the instrument, counted so that they add up: every frame the source delivered was shown,
// dropped (replaced by a newer one before it was processed or before its result was drawn, or decoded
// before a seek), or is still on its way. Rates are over the same recent window.
struct FrameCounts {
    std::uint64_t delivered = 0;
    std::uint64_t shown = 0;
    std::uint64_t dropped = 0;
    double deliveredPerSecond = 0.0;
    double shownPerSecond = 0.0;
};

// Where the source stands: the device's state, and what it says beyond that.
struct SourceState {
    enum class Note {
        None,
        EndOfStream, // the source said it has no more frames
        Paused,      // a replay, paused
        Ended,       // a replay at its end, not looping
    };
    devices::DeviceState device = devices::DeviceState::Closed;
    Note note = Note::None;

    bool operator==(const SourceState&) const = default;
    // "streaming", "paused", "stalled", "end of stream", … as the status line says it.
    std::string text() const;
};

// What the status line and the stats panel say about the source and the engine.
struct InstrumentStatus {
    std::string source; // the device's description
    SourceState state;
    std::string message; // why the source is not running, or its last warning
    bool running = false;
    FrameCounts frames;
    std::optional<double> latencyMs;  // device timestamp to on screen, median; none when clocks differ
    std::optional<double> nominalFps; // what the source announces, when it says
    std::vector<StageSummary> stages; // that ran within the last second, largest first
    bool unregisteredColour = false;  // the source's Capabilities::unregisteredColour
};

struct RecordingStatus {
    bool recording = false;
    std::string path;
    std::uint64_t frames = 0; // accepted into the recording (written or being written)
    std::uint64_t dropped = 0;
    std::uint64_t bytesWritten = 0;
    devices::recording::RecordingOptions options; // how this take stores its frames
    std::chrono::steady_clock::time_point started;
};

// The application: one source (session, replay timeline, recording, export) and the engine that turns its
// frames into what the UI shows (the frame processor, accumulation, stage statistics). Everything here is
// called on the UI thread; the work runs on the session's capture thread, the processor's thread and the
// workers. No GL, no ImGui: `depthcloud record` and the tests drive it without a window.
class Instrument {
public:
    Instrument(std::unique_ptr<devices::Device> device, std::string spec);
    ~Instrument();
    Instrument(const Instrument&) = delete;
    Instrument& operator=(const Instrument&) = delete;

    // Starts the source. One that cannot start (no depth, bad mode) does not fail the instrument: status()
    // says why.
    void start();
    // Opens the source a --source spec names and switches to it; a bad spec leaves the current source
    // running and says why.
    Status openSource(const std::string& spec);
    void switchSource(std::unique_ptr<devices::Device> device, std::string spec);
    const std::string& spec() const { return spec_; }
    const devices::Capabilities& capabilities() const { return session_->capabilities(); }
    // The source's camera controls (null: it has none).
    std::shared_ptr<devices::SensorControls> sensorControls() const { return session_->sensorControls(); }

    // Once per UI frame: what the UI shows now. Returns the demand's generation (results carry it).
    std::uint64_t setDemand(const Demand& demand);
    // Drains the source's events and takes the newest result, if there is one.
    std::optional<processing::ShownFramePtr> update();
    // Waits up to `timeout` for a result that answers the current demand (and, with `newFrame`, comes from
    // a frame not shown yet) and takes it.
    std::optional<processing::ShownFramePtr> waitForResult(std::chrono::milliseconds timeout, bool newFrame);
    // The UI drew `shown` and it is on screen now (after the swap): counts it, and its latency.
    void presented(const processing::ShownFrame& shown);
    // Times measured on the UI thread (drawing, uploads), for the same statistics as the engine's stages.
    void recordStage(std::string_view stage, double milliseconds) { stages_.add(stage, milliseconds); }

    InstrumentStatus status();
    // The timing view of the current source: intervals, latencies, and where each lost frame was lost.
    TimingSummary timing();
    const StageStats& stages() const { return stages_; }
    const FrameProcessor& processor() const { return *processor_; }
    processing::AccumulationWorker& accumulation() { return accumulation_; }

    // The replay's timeline while the source is a replay (null otherwise).
    const std::shared_ptr<devices::replay::ReplayControl>& replay() const { return replay_; }
    // Seeks exactly: the next result is the frame asked for, with temporal state started over.
    void seekReplay(std::size_t index);
    void stepReplay(int frames);
    // Seeks exactly to the frame whose timestamp is nearest `timestampNs` (another replay's clock).
    void seekReplayNear(std::int64_t timestampNs);

    Status startRecording(const std::string& path, const devices::recording::RecordingOptions& options = {});
    // Records into the next numbered take in `directory` (depthcloud-recording-001.dcrec, …); returns its
    // path.
    Expected<std::string> startTake(const std::string& directory,
                                    const devices::recording::RecordingOptions& options);
    Status stopRecording();
    RecordingStatus recording() const;

    // Exports frames [first, end) of the replay (end 0: to the last) in the background, processed as
    // `demand` says.
    Status startExport(exporting::ExportFormat format, const std::string& directory, std::size_t first,
                       std::size_t end, const Demand& demand);
    const ExportJob* exportJob() const { return exportJob_.get(); }
    void cancelExport() {
        if (exportJob_)
            exportJob_->cancel();
    }

private:
    void startSession();
    void drainEvents();
    FrameCounts countFrames();
    // Moves what the session and the processor recorded about each frame into timing_.
    void drainTiming();
    std::optional<processing::ShownFramePtr> handOut(std::optional<processing::ShownFramePtr> result);
    void adoptReplay(devices::Device& device);

    std::string spec_;
    std::shared_ptr<devices::Session> session_;
    std::shared_ptr<devices::replay::ReplayControl> replay_;
    SourceState state_;
    std::string message_;
    bool running_ = false;
    StageStats stages_;
    processing::AccumulationWorker accumulation_;
    std::unique_ptr<FrameProcessor> processor_;
    Demand demand_;
    std::uint64_t demandGeneration_ = 0;
    std::uint64_t lastShownTimestampNs_ = ~0ull;
    std::uint64_t shown_ = 0;
    // The last result handed to the UI in this session: only it can be shown as this session's frame (the
    // UI may still hold, and present, a result of the source it switched away from).
    processing::ShownFramePtr handedOut_;
    base::RollingStats latencyMs_;
    TimingModel timing_;
    struct CountSample {
        std::chrono::steady_clock::time_point at;
        std::uint64_t delivered;
        std::uint64_t shown;
    };
    std::deque<CountSample> countHistory_;
    std::unique_ptr<devices::recording::SessionRecording> recording_;
    devices::recording::RecordingOptions recordingOptions_;
    std::chrono::steady_clock::time_point recordingStarted_;
    std::unique_ptr<ExportJob> exportJob_;
};

} // namespace dc::engine
