#include "ui/viewer.h"

#include "base/log.h"
#include "devices/device.h"
#include "frame/camera_model.h"

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace dc::ui {

namespace {

using Clock = std::chrono::steady_clock;

// Resident memory from /proc, so the stats panel shows what the process really holds.
double residentMebibytes() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    if (!(statm >> pages >> resident))
        return 0.0;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

} // namespace

Viewer::Viewer(engine::Instrument& instrument, render::ViewRenderer& renderer, Settings settings)
    : instrument_(instrument), renderer_(renderer), presenter_(instrument, renderer, std::move(settings)) {
    // Panels are opaque: a panel over the cloud (stats, log, fog, aura, infrared) must not let the points
    // behind it show through and read as part of its picture.
    if (ImGui::GetCurrentContext())
        ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;
    presenter_.setCompanions(&companions_);
}

bool Viewer::update(double timeSeconds, std::chrono::milliseconds wait) {
    if (auto index = std::exchange(pendingRemoval_, std::nullopt))
        companions_.remove(*index);
    if (auto spec = std::exchange(pendingAddition_, std::nullopt))
        (void)addSource(*spec);
    companions_.followReplay(instrument_);
    companions_.update(settings_, timeSeconds);
    const bool fresh = presenter_.update(timeSeconds, wait);
    companions_.noteSkew(instrument_, shown());
    return fresh;
}

Status Viewer::addSource(const std::string& spec) {
    if (Status s = companions_.add(spec, settings_); !s) {
        sourcesPanel_.message = s.error().message;
        logError("source not added: " + s.error().message);
        return s;
    }
    sourcesPanel_.message.clear();
    logInfo("source added: " + spec);
    return {};
}

ProbeSource probeSourceOf(const processing::ShownFramePtr& shown) {
    if (!shown || !shown->depth.data)
        return {};
    const auto& infrared = shown->frame->infrared;
    return {shown->depth.data.get(), shown->depth.intrinsics, shown->pointSeen.get(), shown->frame.get(),
            infrared ? &*infrared : nullptr};
}

ProbeSource Viewer::probeSource() const {
    return probeSourceOf(shown());
}

Status Viewer::openSource(const std::string& spec) {
    if (Status s = instrument_.openSource(spec); !s) {
        sourcePanel_.error = s.error().message;
        return s;
    }
    sourcePanel_.error.clear();
    rememberSource(settings_, spec);
    // Another source means another world: nothing measured in the old one carries over.
    presenter_.forgetShown();
    measured_.reset();
    quality_.log.clear();
    quality_.savedTo.clear();
    return {};
}

Status Viewer::openPath(const std::string& path) {
    Expected<std::string> spec = sourceSpecForPath(path);
    if (!spec) {
        sourcePanel_.error = spec.error().message;
        logWarning(spec.error().message);
        return spec.error();
    }
    return openSource(*spec);
}

namespace {

// "REC 1:05 | 1950 frames | 212.4 MB": how long, how much, how large so far.
std::string recordingText(const engine::RecordingStatus& r) {
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - r.started).count();
    char text[128];
    std::snprintf(text, sizeof text, "REC %lld:%02lld | %llu frames | %.1f MB",
                  static_cast<long long>(seconds / 60), static_cast<long long>(seconds % 60),
                  static_cast<unsigned long long>(r.frames), static_cast<double>(r.bytesWritten) / 1e6);
    return text;
}

} // namespace

StatusLine Viewer::statusLine() {
    const engine::InstrumentStatus s = instrument_.status();
    StatusLine line{s.source,
                    s.state.text(),
                    s.message,
                    s.frames,
                    presenter_.framesPerSecond(),
                    presenter_.pointsShown(),
                    cloudPathText(),
                    {},
                    s.latencyMs,
                    {},
                    {}};
    for (const engine::StageSummary& stage : s.stages)
        line.stageMedians.push_back({stage.name, stage.medianMs});
    if (const engine::RecordingStatus r = instrument_.recording(); r.recording)
        line.recording = recordingText(r);
    if (shown() && shown()->frame && shown()->frame->rig)
        line.calibration = frame::describe(*shown()->frame->rig);
    else if (s.unregisteredColour && shown() && shown()->frame && !shown()->frame->capturedImage.empty())
        line.calibration = devices::kUnregisteredColourMessage;
    return line;
}

void Viewer::measure() {
    const auto now = Clock::now();
    const std::uint64_t version = renderer_.contentVersion();
    // A source that stops delivering (paused, ended, stalled) changes nothing on screen, but its rates fall
    // to zero within the rate window: they are taken again until they have, so no figure looks live.
    const bool ratesMoving =
        measured_ && (measured_->frames.deliveredPerSecond > 0.0 || measured_->frames.shownPerSecond > 0.0);
    if (measured_ && ((version == measuredVersion_ && !ratesMoving) || now - measuredAt_ < kMeasureInterval))
        return;
    measured_ = statsView();
    measuredVersion_ = version;
    measuredAt_ = now;
}

// The status line with the figures measure() took last; what the source is and does is always current.
StatusLine Viewer::shownStatusLine() {
    StatusLine line = statusLine();
    line.frames = measured_->frames;
    line.uiFps = measured_->uiFps;
    line.latencyMs = measured_->latencyMs;
    line.stageMedians.clear();
    for (const StageHistory& stage : measured_->stages)
        line.stageMedians.push_back({stage.name, stage.medianMs});
    return line;
}

StatsView Viewer::statsView() {
    const engine::InstrumentStatus s = instrument_.status();
    StatsView v{s.frames,    presenter_.framesPerSecond(), presenter_.pointsShown(),
                s.latencyMs, residentMebibytes(),          {}};
    for (const engine::StageSummary& stage : s.stages) {
        StageHistory h{stage.name, stage.medianMs, stage.maxMs, {}};
        for (const double ms : stage.history)
            h.history.push_back(static_cast<float>(ms));
        v.stages.push_back(std::move(h));
    }
    return v;
}

} // namespace dc::ui
