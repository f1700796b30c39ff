#pragma once

#include "base/expected.h"
#include "base/rolling_stats.h"
#include "devices/device.h"
#include "engine/instrument.h"
#include "engine/replay_follow.h"
#include "processing/rigid_alignment.h"
#include "render/view_renderer.h"
#include "ui/fused_cloud.h"
#include "ui/presenter.h"
#include "ui/settings.h"
#include "ui/source_settings.h"

#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dc::ui {

// A source beside the main one (--source given again, or "Add source"): its own instrument (session,
// processing, statistics), its own renderer for its panels, its own presenter. Its cloud is not drawn on
// its own: the main presenter draws its points in the fused cloud. Made and used on the GL thread.
class Companion {
public:
    // Processed with `settings` (the main source's) and `own`.
    static Expected<std::unique_ptr<Companion>> create(std::unique_ptr<devices::Device> device,
                                                       std::string spec, const Settings& settings,
                                                       const SourceSettings& own = {});
    Companion(const Companion&) = delete;
    Companion& operator=(const Companion&) = delete;

    engine::Instrument& instrument() { return instrument_; }
    const engine::Instrument& instrument() const { return instrument_; }
    Presenter& presenter() { return *presenter_; }
    const Presenter& presenter() const { return *presenter_; }
    const render::ViewRenderer& renderer() const { return renderer_; }
    render::ViewRenderer& renderer() { return renderer_; }
    CompanionLook look;
    SourceSettings own;                     // its processing: the main source's, or its own
    std::uint64_t gatheredSequence = ~0ull; // the last of its frames handed to the main accumulation
    // The overlap consistency figure with the main source, as placed now (Companions::overlap).
    std::optional<processing::OverlapFigure> overlap;
    std::chrono::steady_clock::time_point overlapAt;
    engine::ReplayFollower follower; // its replay on the main replay's timeline
    // Its frames' skew from the main source's (ms), one sample per pair of frames shown together.
    base::RollingStats skew{240};
    std::pair<std::uint64_t, std::uint64_t> skewPair{~0ull, ~0ull}; // the (main, own) frames sampled last

private:
    Companion(std::unique_ptr<devices::Device> device, std::string spec);

    engine::Instrument instrument_;
    render::ViewRenderer renderer_;
    std::unique_ptr<Presenter> presenter_; // after renderer_ is initialised
};

// Where a further replay's frames fall on the main replay's scrubber: frame `first` and those after it, as
// many as `positions` holds (the frames between the main replay's first and last), each at its place
// between the scrubber's ends (0 the main replay's first frame, 1 its last).
struct TimelinePlaces {
    std::size_t first = 0;
    std::vector<double> positions;
};

// Places the frames stamped `stampsNs` (a further replay's, on its own clock) on the main replay's
// scrubber, stamped `mainStampsNs`: each moves to the main clock as the replays follow each other
// (engine::onCompanionClock) and lands between the main frames around it, at the fraction of their
// interval it is past the earlier one. The scrubber steps by frame, so a place is a fractional frame index
// over the last index.
TimelinePlaces timelinePlaces(const devices::replay::ReplayStatus& main,
                              const std::vector<std::int64_t>& mainStampsNs,
                              const devices::replay::ReplayStatus& further,
                              const std::vector<std::int64_t>& stampsNs);

// A further source's row under the main replay's scrubber: its frames as ticks, the one it shows marked.
struct TimelineSourceRow {
    std::string name; // "Source N", as the Sources panel counts them
    TimelinePlaces places;
    std::optional<std::size_t> shown; // the frame it shows now
    std::string note;                 // said instead of ticks: why it has none (a live source)
};

// What the Timing panel reads out of a further source's skew samples (ms).
struct SkewFigures {
    std::size_t count = 0;
    double medianMs = 0.0; // of two middle samples, their mean
    double minMs = 0.0;
    double maxMs = 0.0;
    float toleranceMs = 0.0f;        // the pairing tolerance; 0: off
    std::size_t beyondTolerance = 0; // samples whose size is above it, as paired() judges; 0 while off
    // From the smallest sample to the largest, widened to the tolerance's -/+ lines while it is on.
    engine::IntervalHistogram histogram;
};
SkewFigures skewFigures(const std::vector<double>& samplesMs, float pairingToleranceMs);

// A further source's skew from the main source, as the Timing panel shows it.
struct SourceSkew {
    std::string name;            // "Source N"
    std::optional<double> nowMs; // its shown frame's time less the main source's (Companions::skewMs)
    SkewFigures recent;          // over its recent samples (Companion::skew)
    std::string note;            // why it has none (no common clock); empty when it can have some
};

// Companion `index` as the panels name it: the main source is source 1.
std::string sourceName(std::size_t index);

// The companions of the main source, in the order they were added.
class Companions {
public:
    // Opens `spec` and starts it beside the main source, processed with `settings`.
    Status add(const std::string& spec, const Settings& settings);
    void add(std::unique_ptr<Companion> companion) { companions_.push_back(std::move(companion)); }
    void remove(std::size_t index);
    std::size_t size() const { return companions_.size(); }
    bool empty() const { return companions_.empty(); }
    Companion& operator[](std::size_t i) { return *companions_[i]; }
    const Companion& operator[](std::size_t i) const { return *companions_[i]; }

    // Once per UI frame, before the main presenter's update: each companion follows the main settings
    // (its processing and confidence only while it has none of its own) and takes its newest result.
    // Returns whether any had a new frame.
    bool update(const Settings& main, double timeSeconds);
    // In accumulate mode, after the main presenter's update: each visible companion's frames not handed over
    // yet join the main source's world cloud, placed in the world as the fused cloud places them and kept
    // from the companion's own confidence level; each companion has its own latest-wins slot there.
    void gather(processing::AccumulationWorker& world, const Settings& main);
    // Companion replays follow the main source's replay (its seeks, steps, play state, speed, loop).
    void followReplay(const engine::Instrument& main);
    // What the companions' updates took is on screen now (each counts its own frame shown).
    void presented();
    // The visible companions' shown results, each placed in the world.
    std::vector<FusedSource> fusedSources() const;
    // Refines companion `index`'s placement against the main source's shown frame by point-to-plane ICP,
    // seeded by where both sit now; its correction takes the result. Says why when there is nothing to
    // refine.
    Expected<processing::IcpResult> refine(std::size_t index, const processing::ShownFramePtr& main);
    // The overlap consistency figure of companion `index` against the main source, as placed now (taken
    // at most twice a second; none before both have a frame).
    const std::optional<processing::OverlapFigure>& overlap(std::size_t index,
                                                            const processing::ShownFramePtr& main);

    // How far companion `index`'s shown frame is from the main source's in time (ms, positive: later), on
    // their common clock: replays' as ReplayFollower maps them, live sources' own stamps. None when one
    // has no frame, or one is a replay and the other not.
    std::optional<double> skewMs(std::size_t index, const engine::Instrument& main,
                                 const processing::ShownFramePtr& mainShown) const;
    // Every source's placement (its pose= value; for a companion, after its correction) written into a new
    // folder under `parent`: rig.yaml (OpenCV extrinsics, camera_0 the main source, camera_N source N+1)
    // and, when the main source sits at the world's origin, camchain.yaml (Kalibr). Returns the files.
    Expected<std::vector<std::string>> savePlacements(const std::string& mainSpec,
                                                      const std::string& parent) const;
    // Samples each companion's skew once per pair of frames shown together (after the main update).
    void noteSkew(const engine::Instrument& main, const processing::ShownFramePtr& mainShown);
    // Whether companion `index`'s frame is close enough in time to the main source's to be fused with it:
    // always with no tolerance (0) or no common clock.
    bool paired(std::size_t index, const engine::Instrument& main, const processing::ShownFramePtr& mainShown,
                float toleranceMs) const;
    // Each companion's panels in a folder of its own under `directory` (source-2, source-3, ... as they
    // were added); returns the files written, each with its folder.
    Expected<std::vector<std::string>> savePanels(const std::string& directory);
    // Each companion's run figures (summary.json), with its overlap figure with the main source taken now
    // and its skew.
    std::vector<ViewerSummary> summaries(const engine::Instrument& main,
                                         const processing::ShownFramePtr& mainShown);
    // Each companion's row under the main replay's scrubber (none while the main source is no replay): a
    // replay's frames placed on the common clock and the frame it shows; a live source, that it has none.
    std::vector<TimelineSourceRow> timelineRows(const engine::Instrument& main) const;
    // Each companion's skew from the main source for the Timing panel: now, and its recent samples'
    // figures against the pairing tolerance (0: off).
    std::vector<SourceSkew> skewRows(const engine::Instrument& main,
                                     const processing::ShownFramePtr& mainShown,
                                     float pairingToleranceMs) const;

private:
    std::vector<std::unique_ptr<Companion>> companions_;
};

// The transform from the main source's camera to companion's camera, as both are placed now.
frame::RigidTransform mainToCompanion(const processing::ShownFrame& main, const Companion& companion);

} // namespace dc::ui
