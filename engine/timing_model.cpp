#include "engine/timing_model.h"

#include <algorithm>
#include <cmath>

namespace dc::engine {

namespace {

double milliseconds(std::int64_t ns) {
    return static_cast<double>(ns) / 1e6;
}

// A sequence that went backwards by this much or more restarted (a reconnected or restarted stream), and
// one that moved forward by less wrapped around 2^32 in between: then the unsigned difference is the gap.
constexpr std::uint32_t kRestartDistance = 1u << 31;

// The depth stamp marks the sensor's time on this machine's clock, so that the screen's time minus it is
// a latency from the sensor.
bool marksSensor(const frame::StreamTiming& t) {
    return t.monotonic && t.sensorNs > 0 &&
           (t.source == frame::TimestampSource::StartOfExposure ||
            t.source == frame::TimestampSource::EndOfFrame);
}

} // namespace

const char* toString(frame::TimestampSource source) {
    switch (source) {
    case frame::TimestampSource::Unknown:
        break;
    case frame::TimestampSource::StartOfExposure:
        return "start of exposure";
    case frame::TimestampSource::EndOfFrame:
        return "end of frame";
    case frame::TimestampSource::Arrival:
        return "arrival (driver's clock not monotonic)";
    }
    return "not given by the source";
}

DurationFigures durationFigures(const std::vector<double>& samples) {
    if (samples.empty())
        return {};
    std::vector<double> sorted = samples;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    const double median = n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(n)));
    return {n, median, sorted[std::max<std::size_t>(rank, 1) - 1]};
}

IntervalHistogram intervalHistogram(const std::vector<double>& samples, int bins) {
    if (samples.empty() || bins <= 0)
        return {};
    const auto [low, high] = std::minmax_element(samples.begin(), samples.end());
    IntervalHistogram h{*low, *high > *low ? (*high - *low) / bins : 1.0,
                        std::vector<float>(static_cast<std::size_t>(bins), 0.0f)};
    for (const double v : samples) {
        const auto bin = static_cast<int>((v - h.lowMs) / h.binMs);
        h.counts[static_cast<std::size_t>(std::clamp(bin, 0, bins - 1))] += 1.0f;
    }
    return h;
}

std::uint64_t TimingModel::observe(Stream& s, const frame::StreamTiming& t, std::int64_t timestampNs) {
    ++s.frames;
    s.source = t.source;
    s.monotonic = t.monotonic;
    if (s.lastNs && timestampNs > *s.lastNs)
        s.intervalsMs.add(milliseconds(timestampNs - *s.lastNs));
    s.lastNs = timestampNs; // a replay that loops or seeks starts its intervals again
    std::uint64_t missing = 0;
    if (t.driverSequence && s.lastSequence && *t.driverSequence != *s.lastSequence) {
        const std::uint32_t step = *t.driverSequence - *s.lastSequence; // modulo 2^32
        missing = step < kRestartDistance ? step - 1u : 0u;
    }
    s.lastSequence = t.driverSequence;
    return missing;
}

void TimingModel::delivered(const devices::FrameRecord& r) {
    ++delivered_;
    if (r.seekGeneration != seekGeneration_) {
        // After a seek the recorded stream resumes elsewhere: neither its sequence gap nor its interval is
        // one.
        seekGeneration_ = r.seekGeneration;
        for (Stream* s : {&depth_, colour_ ? &*colour_ : nullptr}) {
            if (s) {
                s->lastSequence.reset();
                s->lastNs.reset();
            }
        }
    }
    drops_.cameraUsb += observe(depth_, r.timing.depth, r.timestampNs);
    if (r.timing.colour) {
        if (!colour_)
            colour_.emplace();
        observe(*colour_, *r.timing.colour, r.timing.colour->sensorNs);
        if (r.timing.colour->sensorNs > 0 && r.timing.depth.sensorNs > 0)
            colourSkewMs_.add(std::abs(milliseconds(r.timing.colour->sensorNs - r.timing.depth.sensorNs)));
    }
    InFlight f;
    f.arrivalNs = r.atNs;
    if (marksSensor(r.timing.depth))
        f.sensorNs = r.timing.depth.sensorNs;
    inFlight_[r.sequence] = f;
    // A frame that never ends here (its processing failed) must not be kept for ever.
    while (inFlight_.size() > kWindow)
        inFlight_.erase(inFlight_.begin());
}

void TimingModel::add(const devices::FrameRecord& r) {
    switch (r.kind) {
    case devices::FrameRecord::Kind::Delivered:
        delivered(r);
        return;
    case devices::FrameRecord::Kind::Replaced:
        ++drops_.replacedBeforeProcessing;
        inFlight_.erase(r.sequence);
        return;
    }
}

void TimingModel::add(const ProcessorRecord& r) {
    switch (r.kind) {
    case ProcessorRecord::Kind::Processed:
        if (const auto it = inFlight_.find(r.sequence); it != inFlight_.end()) {
            it->second.startNs = r.startNs;
            it->second.endNs = r.endNs;
            waitMs_.add(milliseconds(r.startNs - it->second.arrivalNs));
            processingMs_.add(milliseconds(r.endNs - r.startNs));
        }
        return;
    case ProcessorRecord::Kind::Unshown:
        ++drops_.replacedBeforeDisplay;
        inFlight_.erase(r.sequence);
        return;
    case ProcessorRecord::Kind::Skipped:
        ++drops_.skipped;
        inFlight_.erase(r.sequence);
        return;
    }
}

void TimingModel::shown(std::uint64_t sequence, std::int64_t shownNs) {
    ++shown_;
    const auto it = inFlight_.find(sequence);
    if (it == inFlight_.end())
        return;
    const InFlight& f = it->second;
    arrivalToShownMs_.add(milliseconds(shownNs - f.arrivalNs));
    if (f.sensorNs)
        sensorToShownMs_.add(milliseconds(shownNs - *f.sensorNs));
    if (f.endNs > 0)
        processedToShownMs_.add(milliseconds(shownNs - f.endNs));
    inFlight_.erase(it);
}

StreamTimingSummary TimingModel::summarise(const Stream& s) {
    const std::vector<double> intervals = s.intervalsMs.inOrder();
    return {s.frames,
            s.source,
            s.monotonic,
            s.lastSequence,
            durationFigures(intervals),
            intervalHistogram(intervals, kHistogramBins)};
}

TimingSummary TimingModel::summary() const {
    TimingSummary t;
    t.depth = summarise(depth_);
    if (colour_)
        t.colour = summarise(*colour_);
    t.delivered = delivered_;
    t.shown = shown_;
    t.drops = drops_;
    t.arrivalToShown = durationFigures(arrivalToShownMs_.inOrder());
    t.sensorToShown = durationFigures(sensorToShownMs_.inOrder());
    t.waitBeforeProcessing = durationFigures(waitMs_.inOrder());
    t.processing = durationFigures(processingMs_.inOrder());
    t.processedToShown = durationFigures(processedToShownMs_.inOrder());
    if (colourSkewMs_.count() > 0)
        t.colourSkew = durationFigures(colourSkewMs_.inOrder());
    return t;
}

} // namespace dc::engine
