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

private:
    std::vector<std::unique_ptr<Companion>> companions_;
};

// The transform from the main source's camera to companion's camera, as both are placed now.
frame::RigidTransform mainToCompanion(const processing::ShownFrame& main, const Companion& companion);

} // namespace dc::ui
