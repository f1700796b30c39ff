#pragma once

#include "base/rolling_stats.h"
#include "devices/session.h"
#include "engine/frame_processor.h"
#include "frame/frame.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace dc::engine {

// Where the frames that never reached the screen were lost, one count per place.
struct DropCounts {
    std::uint64_t cameraUsb = 0; // never reached the application: gaps in the driver's sequence
    std::uint64_t replacedBeforeProcessing = 0; // replaced in the session's latest-wins slot
    std::uint64_t skipped = 0;               // taken but not new: decoded before a seek, or delivered twice
    std::uint64_t replacedBeforeDisplay = 0; // its result replaced before the GL thread took it

    // The frames the application had and did not show: what FrameCounts::dropped counts.
    std::uint64_t afterArrival() const { return replacedBeforeProcessing + skipped + replacedBeforeDisplay; }
};

// A duration over the recent frames, in milliseconds.
struct DurationFigures {
    std::size_t count = 0;
    double medianMs = 0.0;
    double p99Ms = 0.0; // nearest rank: the smallest sample at least 99 % of the samples do not exceed
};

// The recent frame intervals in equal bins from the shortest to the longest: a steady camera is one spike,
// jitter widens it, a lost frame is a bar at twice the period.
struct IntervalHistogram {
    double lowMs = 0.0;
    double binMs = 0.0;
    std::vector<float> counts; // float: what ImGui::PlotHistogram draws
};

// One stream of the source (the depth frames, or the colour images paired with them).
struct StreamTimingSummary {
    std::uint64_t frames = 0;
    frame::TimestampSource source = frame::TimestampSource::Unknown; // as its latest frame said
    bool monotonic = false;
    std::optional<std::uint32_t> lastDriverSequence;
    DurationFigures intervals; // between consecutive frames' timestamps
    IntervalHistogram histogram;
};

struct TimingSummary {
    StreamTimingSummary depth;
    std::optional<StreamTimingSummary> colour; // when frames carry a colour node's image
    std::uint64_t delivered = 0;
    std::uint64_t shown = 0;
    DropCounts drops;
    DurationFigures arrivalToShown;
    // From the depth timestamp's instant (start of exposure or end of frame) to the screen; only for
    // timestamps on this machine's CLOCK_MONOTONIC that mark the sensor's time.
    DurationFigures sensorToShown;
    DurationFigures waitBeforeProcessing;      // arrival to processing start
    DurationFigures processing;                // processing start to end
    DurationFigures processedToShown;          // processing end to on screen
    std::optional<DurationFigures> colourSkew; // |colour - depth| timestamps of paired frames
    std::uint64_t recordsLost = 0;             // records nobody drained in time: counts may be short
};

const char* toString(frame::TimestampSource source);

// The timing view's model: fed, in order, with what happened to each frame (the session's and the
// processor's records, and when the UI showed it), it keeps per stream the intervals and the driver's
// sequence, per frame the times from arrival to screen, and attributes every frame lost to where it was.
// Pure and single-threaded: the Instrument drains the records into it on the UI thread.
class TimingModel {
public:
    static constexpr std::size_t kWindow = 512; // the recent frames the figures are over
    static constexpr int kHistogramBins = 24;

    void add(const devices::FrameRecord& record);
    void add(const ProcessorRecord& record);
    void shown(std::uint64_t sequence, std::int64_t shownNs);
    void reset() { *this = TimingModel(); }

    TimingSummary summary() const;

private:
    struct Stream {
        std::uint64_t frames = 0;
        frame::TimestampSource source = frame::TimestampSource::Unknown;
        bool monotonic = false;
        std::optional<std::uint32_t> lastSequence;
        std::optional<std::int64_t> lastNs;
        base::RollingStats intervalsMs{kWindow};
    };
    // A frame between arrival and the screen.
    struct InFlight {
        std::int64_t arrivalNs = 0;
        std::optional<std::int64_t> sensorNs; // comparable with arrivalNs
        std::int64_t startNs = 0;
        std::int64_t endNs = 0;
    };

    // Returns the frames missing from the driver's sequence before this one.
    static std::uint64_t observe(Stream& stream, const frame::StreamTiming& timing, std::int64_t timestampNs);
    void delivered(const devices::FrameRecord& record);
    static StreamTimingSummary summarise(const Stream& stream);

    Stream depth_;
    std::optional<Stream> colour_;
    std::uint64_t seekGeneration_ = 0; // of the last delivered frame
    std::map<std::uint64_t, InFlight> inFlight_;
    std::uint64_t delivered_ = 0;
    std::uint64_t shown_ = 0;
    DropCounts drops_;
    base::RollingStats arrivalToShownMs_{kWindow};
    base::RollingStats sensorToShownMs_{kWindow};
    base::RollingStats waitMs_{kWindow};
    base::RollingStats processingMs_{kWindow};
    base::RollingStats processedToShownMs_{kWindow};
    base::RollingStats colourSkewMs_{kWindow};
};

// The median and nearest-rank 99th percentile of `samples`.
DurationFigures durationFigures(const std::vector<double>& samples);
// `samples` in `bins` equal bins from their smallest to their largest (one bin 1 ms wide when all equal).
IntervalHistogram intervalHistogram(const std::vector<double>& samples, int bins);

} // namespace dc::engine
