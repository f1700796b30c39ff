#include "ui/companions.h"

#include "base/files.h"
#include "devices/source_pose.h"
#include "devices/source_spec.h"
#include "frame/multi_camera_extrinsics.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace dc::ui {

namespace {

// The overlap figure is taken this often at most: it pairs every other sample of the main cloud.
constexpr std::chrono::milliseconds kOverlapInterval{500};

processing::DepthCloud depthCloudOf(const processing::ShownFrame& shown) {
    return {shown.depth.data.get(), shown.depth.intrinsics};
}

} // namespace

Companion::Companion(std::unique_ptr<devices::Device> device, std::string spec)
    : instrument_(std::move(device), std::move(spec)) {}

Expected<std::unique_ptr<Companion>> Companion::create(std::unique_ptr<devices::Device> device,
                                                       std::string spec, const Settings& settings,
                                                       const SourceSettings& own) {
    std::unique_ptr<Companion> c(new Companion(std::move(device), std::move(spec)));
    if (Status s = c->renderer_.init(); !s)
        return s.error();
    c->own = own;
    c->presenter_ =
        std::make_unique<Presenter>(c->instrument_, c->renderer_, furtherSourceSettings(settings, own));
    c->presenter_->setDrawsCloud(false);
    c->instrument_.start();
    return c;
}

Status Companions::add(const std::string& spec, const Settings& settings) {
    auto device = devices::openSourceSpec(spec);
    if (!device)
        return Error{spec + ": " + device.error().message};
    auto companion = Companion::create(std::move(*device), spec, settings);
    if (!companion)
        return companion.error();
    companions_.push_back(std::move(*companion));
    return {};
}

void Companions::remove(std::size_t index) {
    if (index < companions_.size())
        companions_.erase(companions_.begin() + static_cast<std::ptrdiff_t>(index));
}

bool Companions::update(const Settings& main, double timeSeconds) {
    bool fresh = false;
    for (auto& c : companions_) {
        followMain(c->own, main);
        c->presenter().setGathered(main.accumulate.enabled);
        c->presenter().settings() = furtherSourceSettings(main, c->own);
        fresh |= c->presenter().update(timeSeconds);
    }
    return fresh;
}

void Companions::gather(processing::AccumulationWorker& world, const Settings& main) {
    const AccumulateSettings& a = main.accumulate;
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        Companion& c = *companions_[i];
        const processing::ShownFramePtr& shown = c.presenter().shown();
        if (!c.look.visible || !shown || !shown->depth.data || shown->frame->sequence == c.gatheredSequence)
            continue;
        c.gatheredSequence = shown->frame->sequence;
        const frame::Pose pose = frame::poseFromRigid(placeInWorld(*shown->frame, c.look.correction));
        const frame::Confidence level = c.own.followsMain ? main.cloud.minConfidence : c.own.minConfidence;
        world.submit({shown->depth.data, shown->depth.intrinsics, shown->pointColours, pose, level,
                      main.cloud.nearMeters, static_cast<std::size_t>(a.budgetThousands) * 1000,
                      a.voxelMillimeters * 1e-3f},
                     i + 1);
    }
}

void Companions::followReplay(const engine::Instrument& main) {
    if (!main.replay())
        return;
    const devices::replay::ReplayStatus status = main.replay()->status();
    for (auto& c : companions_)
        c->follower.follow(status, c->instrument());
}

void Companions::presented() {
    for (auto& c : companions_)
        c->presenter().presented();
}

std::vector<FusedSource> Companions::fusedSources() const {
    std::vector<FusedSource> out;
    for (const auto& c : companions_) {
        const processing::ShownFramePtr& shown = c->presenter().shown();
        if (c->look.visible && shown)
            out.push_back({shown, placeInWorld(*shown->frame, c->look.correction), c->instrument().spec(),
                           c->own.followsMain ? std::nullopt : std::optional(c->own.minConfidence)});
    }
    return out;
}

frame::RigidTransform mainToCompanion(const processing::ShownFrame& main, const Companion& companion) {
    const frame::RigidTransform mainToWorld = placeInWorld(*main.frame, {});
    const frame::RigidTransform companionToWorld =
        placeInWorld(*companion.presenter().shown()->frame, companion.look.correction);
    return frame::compose(frame::inverse(companionToWorld), mainToWorld);
}

Expected<processing::IcpResult> Companions::refine(std::size_t index, const processing::ShownFramePtr& main) {
    if (index >= companions_.size())
        return Error{"no such source"};
    Companion& c = *companions_[index];
    const processing::ShownFramePtr& own = c.presenter().shown();
    if (!main || !own || !main->depth.data || !own->depth.data)
        return Error{"both sources need a frame first"};
    const frame::RigidTransform seed = mainToCompanion(*main, c);
    processing::IcpResult r = processing::refineAlignment(depthCloudOf(*main), depthCloudOf(*own), seed);
    if (r.status == processing::IcpStatus::InvalidInput || r.status == processing::IcpStatus::TooFewPoints)
        return Error{std::string("ICP: ") + processing::toString(r.status) + " (" +
                     std::to_string(r.before.count) + " overlapping samples)"};
    // The companion's camera-to-world that makes main -> companion the refined transform, with the main
    // source where it is; its correction is what takes its own placement there.
    const frame::RigidTransform refined =
        frame::compose(placeInWorld(*main->frame, {}), frame::inverse(r.aToB));
    const frame::RigidTransform placed = placeInWorld(*own->frame, {});
    c.look.correction = frame::compose(refined, frame::inverse(placed));
    c.overlap = r.after;
    c.overlapAt = std::chrono::steady_clock::now();
    return r;
}

const std::optional<processing::OverlapFigure>& Companions::overlap(std::size_t index,
                                                                    const processing::ShownFramePtr& main) {
    static const std::optional<processing::OverlapFigure> kNone;
    if (index >= companions_.size())
        return kNone;
    Companion& c = *companions_[index];
    const auto now = std::chrono::steady_clock::now();
    const processing::ShownFramePtr& own = c.presenter().shown();
    if (main && own && main->depth.data && own->depth.data && now - c.overlapAt >= kOverlapInterval) {
        c.overlap = processing::overlapConsistency(depthCloudOf(*main), depthCloudOf(*own),
                                                   mainToCompanion(*main, c));
        c.overlapAt = now;
    }
    return c.overlap;
}

std::optional<double> Companions::skewMs(std::size_t index, const engine::Instrument& main,
                                         const processing::ShownFramePtr& mainShown) const {
    if (index >= companions_.size())
        return std::nullopt;
    const Companion& c = *companions_[index];
    const processing::ShownFramePtr& own = c.presenter().shown();
    const auto& mainReplay = main.replay();
    const auto& ownReplay = c.instrument().replay();
    if (!mainShown || !own || static_cast<bool>(mainReplay) != static_cast<bool>(ownReplay))
        return std::nullopt;
    std::int64_t mainStamp = mainShown->frame->timestampNs;
    if (mainReplay)
        mainStamp = engine::onCompanionClock(mainReplay->status(), mainStamp, ownReplay->status());
    return static_cast<double>(own->frame->timestampNs - mainStamp) * 1e-6;
}

void Companions::noteSkew(const engine::Instrument& main, const processing::ShownFramePtr& mainShown) {
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        Companion& c = *companions_[i];
        const auto skew = skewMs(i, main, mainShown);
        if (!skew)
            continue;
        const std::pair pair{mainShown->frame->sequence, c.presenter().shown()->frame->sequence};
        if (pair != c.skewPair) {
            c.skewPair = pair;
            c.skew.add(*skew);
        }
    }
}

bool Companions::paired(std::size_t index, const engine::Instrument& main,
                        const processing::ShownFramePtr& mainShown, float toleranceMs) const {
    if (toleranceMs <= 0.0f)
        return true;
    const auto skew = skewMs(index, main, mainShown);
    return !skew || std::abs(*skew) <= toleranceMs;
}

Expected<std::vector<std::string>> Companions::savePlacements(const std::string& mainSpec,
                                                              const std::string& parent) const {
    frame::CameraExtrinsicsSet rig{{}, {}};
    const auto placementOf = [](const std::string& spec) -> Expected<frame::RigidTransform> {
        auto placement = devices::sourcePlacement(spec);
        if (!placement)
            return placement.error();
        return placement->cameraToWorld.value_or(frame::RigidTransform{});
    };
    auto main = placementOf(mainSpec);
    if (!main)
        return main.error();
    rig.cameras.push_back({"main", *main});
    for (const auto& c : companions_) {
        auto own = placementOf(c->instrument().spec());
        if (!own)
            return own.error();
        rig.cameras.push_back({c->instrument().spec(), frame::compose(c->look.correction, *own)});
    }
    auto opencv = frame::writeCameraExtrinsics(rig, frame::ExtrinsicsFormat::OpenCvYaml);
    if (!opencv)
        return opencv.error();
    // Kalibr's world is its first camera's frame: without the main source there, the chain would not say
    // where the rig is.
    auto kalibr = frame::writeCameraExtrinsics(rig, frame::ExtrinsicsFormat::KalibrCamchain);
    auto dir = base::createFreshDirectory(parent, "placements");
    if (!dir)
        return dir.error();
    std::vector<std::string> written{*dir + "/rig.yaml"};
    if (Status s = base::writeTextFile(written[0], *opencv); !s)
        return s.error();
    if (kalibr) {
        written.push_back(*dir + "/camchain.yaml");
        if (Status s = base::writeTextFile(written[1], *kalibr); !s)
            return s.error();
    }
    return written;
}

Expected<std::vector<std::string>> Companions::savePanels(const std::string& directory) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        const std::string folder = "source-" + std::to_string(i + 2);
        std::error_code ec;
        std::filesystem::create_directories(directory + "/" + folder, ec);
        if (ec)
            return Error{directory + "/" + folder + ": " + ec.message()};
        auto written = companions_[i]->presenter().savePanels(directory + "/" + folder);
        if (!written)
            return written.error();
        for (const std::string& name : *written)
            names.push_back(folder + "/" + name);
    }
    return names;
}

std::vector<ViewerSummary> Companions::summaries(const engine::Instrument& main,
                                                 const processing::ShownFramePtr& mainShown) {
    std::vector<ViewerSummary> out;
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        companions_[i]->overlapAt = {}; // taken now, for the frames shown now
        ViewerSummary s = companions_[i]->presenter().summary();
        s.overlap = overlap(i, mainShown);
        const base::RollingStats& skew = companions_[i]->skew;
        s.skewMs = skew.count() > 0 ? std::optional(skew.median()) : skewMs(i, main, mainShown);
        out.push_back(std::move(s));
    }
    return out;
}

std::vector<TimelineSourceRow> Companions::timelineRows(const engine::Instrument& main) const {
    std::vector<TimelineSourceRow> rows;
    const auto& mainReplay = main.replay();
    if (!mainReplay)
        return rows;
    const devices::replay::ReplayStatus mainStatus = mainReplay->status();
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        const Companion& c = *companions_[i];
        TimelineSourceRow& row = rows.emplace_back();
        row.name = sourceName(i);
        const auto& own = c.instrument().replay();
        if (!own) {
            row.note = "live: no common clock with the replay";
            continue;
        }
        row.places =
            timelinePlaces(mainStatus, mainReplay->timestampsNs(), own->status(), own->timestampsNs());
        const processing::ShownFramePtr& shown = c.presenter().shown();
        if (shown && shown->frame->replay)
            row.shown = shown->frame->replay->index;
    }
    return rows;
}

std::vector<SourceSkew> Companions::skewRows(const engine::Instrument& main,
                                             const processing::ShownFramePtr& mainShown,
                                             float pairingToleranceMs) const {
    std::vector<SourceSkew> rows;
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        const Companion& c = *companions_[i];
        SourceSkew& row = rows.emplace_back();
        row.name = sourceName(i);
        if (static_cast<bool>(main.replay()) != static_cast<bool>(c.instrument().replay()))
            row.note = "no common clock: one is a replay, the other live";
        row.nowMs = skewMs(i, main, mainShown);
        row.recent = skewFigures(c.skew.inOrder(), pairingToleranceMs);
    }
    return rows;
}

TimelinePlaces timelinePlaces(const devices::replay::ReplayStatus& main,
                              const std::vector<std::int64_t>& mainStampsNs,
                              const devices::replay::ReplayStatus& further,
                              const std::vector<std::int64_t>& stampsNs) {
    TimelinePlaces places;
    if (mainStampsNs.empty())
        return places;
    // The common clock moves every stamp by as much: where the main replay's first frame falls on the
    // further one's clock, less that frame's own stamp.
    const std::int64_t offsetNs =
        engine::onCompanionClock(main, main.firstTimestampNs, further) - main.firstTimestampNs;
    const double lastIndex = static_cast<double>(mainStampsNs.size() - 1);
    std::size_t before = 0; // the last main frame not after the stamp
    for (std::size_t i = 0; i < stampsNs.size(); ++i) {
        const std::int64_t t = stampsNs[i] - offsetNs;
        if (t < mainStampsNs.front()) {
            places.first = i + 1;
            continue;
        }
        if (t > mainStampsNs.back())
            break;
        while (before + 1 < mainStampsNs.size() && mainStampsNs[before + 1] <= t)
            ++before;
        double index = static_cast<double>(before);
        if (before + 1 < mainStampsNs.size())
            index += static_cast<double>(t - mainStampsNs[before]) /
                     static_cast<double>(mainStampsNs[before + 1] - mainStampsNs[before]);
        places.positions.push_back(lastIndex > 0.0 ? index / lastIndex : 0.0);
    }
    return places;
}

namespace {

// As many bins as the Timing panel's interval histograms (engine::TimingModel's).
constexpr int kSkewBins = 24;

// `samples` in `bins` equal bins from `lowMs` to `highMs` (one bin 1 ms wide when they are equal).
engine::IntervalHistogram histogramOver(const std::vector<double>& samples, double lowMs, double highMs,
                                        int bins) {
    engine::IntervalHistogram h{lowMs, highMs > lowMs ? (highMs - lowMs) / bins : 1.0,
                                std::vector<float>(static_cast<std::size_t>(bins), 0.0f)};
    for (const double v : samples) {
        const auto bin = static_cast<int>((v - h.lowMs) / h.binMs);
        h.counts[static_cast<std::size_t>(std::clamp(bin, 0, bins - 1))] += 1.0f;
    }
    return h;
}

} // namespace

SkewFigures skewFigures(const std::vector<double>& samplesMs, float pairingToleranceMs) {
    SkewFigures f;
    f.count = samplesMs.size();
    f.toleranceMs = std::max(pairingToleranceMs, 0.0f);
    if (samplesMs.empty())
        return f;
    std::vector<double> sorted = samplesMs;
    std::sort(sorted.begin(), sorted.end());
    f.minMs = sorted.front();
    f.maxMs = sorted.back();
    const std::size_t mid = sorted.size() / 2;
    f.medianMs = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
    const double tolerance = f.toleranceMs;
    double low = f.minMs;
    double high = f.maxMs;
    if (tolerance > 0.0) {
        f.beyondTolerance = static_cast<std::size_t>(
            std::count_if(sorted.begin(), sorted.end(), [&](double v) { return std::abs(v) > tolerance; }));
        low = std::min(low, -tolerance);
        high = std::max(high, tolerance);
    }
    f.histogram = histogramOver(samplesMs, low, high, kSkewBins);
    return f;
}

std::string sourceName(std::size_t index) {
    return "Source " + std::to_string(index + 2);
}

} // namespace dc::ui
