#include "base/files.h"
#include "base/log.h"
#include "render/gl_context.h"
#include "tool/options.h"
#include "tool/summary.h"
#include "ui/companions.h"
#include "ui/presenter.h"

#include <cstdio>
#include <thread>

namespace dc::tool {

namespace {

// The cloud snapshot's size: the sample's landscape 4:3.
constexpr int kCloudWidth = 960;
constexpr int kCloudHeight = 720;
// A source that delivers nothing for this long is reported instead of waited on forever; one that delivers
// is waited on for its results up to kLongestWait.
constexpr std::chrono::seconds kFrameTimeout{5};
constexpr std::chrono::seconds kLongestWait{60};
// Headless runs animate on a fixed clock so that the same command writes the same cloud.png.
constexpr double kHeadlessFrameSeconds = 1.0 / 60.0;

bool replayEnded(const engine::Instrument& instrument) {
    const auto& replay = instrument.replay();
    return replay && replay->status().atEnd && !replay->status().loop;
}

// How long a headless run waits: kFrameTimeout while the source delivers nothing; while it delivers, on,
// up to kLongestWait in all, since a loaded machine can take seconds to turn a frame into a result (the
// kernel tier's camera under emulation, beside two busy processes, took 3.6 s a frame).
class Patience {
public:
    explicit Patience(engine::Instrument& instrument)
        : instrument_(instrument), delivered_(delivered()), start_(Clock::now()), lastDelivery_(start_) {}

    bool keepWaiting() {
        const auto now = Clock::now();
        if (const std::uint64_t d = delivered(); d != delivered_) {
            delivered_ = d;
            lastDelivery_ = now;
        }
        return now - lastDelivery_ < kFrameTimeout && now - start_ < kLongestWait;
    }
    long long secondsWaited() const {
        return std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - start_).count();
    }

private:
    using Clock = std::chrono::steady_clock;
    std::uint64_t delivered() { return instrument_.status().frames.delivered; }

    engine::Instrument& instrument_;
    std::uint64_t delivered_;
    Clock::time_point start_, lastDelivery_;
};

// Waits for the next frame's result while Patience allows, in short slices so that the end of a recording
// is noticed at once rather than after the whole timeout.
bool waitForFrame(ui::Presenter& presenter, ui::Companions& companions, double timeSeconds) {
    constexpr std::chrono::milliseconds kSlice{50};
    for (Patience patience(presenter.instrument()); patience.keepWaiting();) {
        // The companions first, so that the fused cloud has their newest frames.
        companions.followReplay(presenter.instrument());
        companions.update(presenter.settings(), timeSeconds);
        const bool fresh = presenter.update(timeSeconds, kSlice);
        companions.noteSkew(presenter.instrument(), presenter.shown());
        if (fresh)
            return true;
        // The last frame may have arrived just before the end was flagged.
        if (replayEnded(presenter.instrument()))
            return presenter.update(timeSeconds, kSlice);
    }
    return false;
}

void presented(ui::Presenter& presenter, ui::Companions& companions) {
    presenter.presented();
    companions.presented();
}

// Every companion's first frame, so that the fused cloud and each source's panels show it: waited for as
// long as its source keeps delivering (Patience), each UI frame drawn and presented as in the window.
Status waitForCompanions(ui::Presenter& presenter, ui::Companions& companions, double timeSeconds) {
    for (std::size_t i = 0; i < companions.size(); ++i) {
        for (Patience patience(companions[i].instrument());
             !companions[i].presenter().shown() && patience.keepWaiting();) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            companions.update(presenter.settings(), timeSeconds);
            presenter.update(timeSeconds);
            presented(presenter, companions);
        }
        if (!companions[i].presenter().shown()) {
            const engine::InstrumentStatus s = companions[i].instrument().status();
            return Error{"no frame from " + s.source + (s.message.empty() ? "" : ": " + s.message)};
        }
    }
    return {};
}

Expected<ui::Companions> startCompanions(const ViewerOptions& options, Devices devices,
                                         const ui::Settings& settings) {
    auto own = furtherSourcesSettings(settings, options);
    if (!own)
        return own.error();
    ui::Companions companions;
    for (std::size_t i = 0; i < devices.size(); ++i) {
        auto c = ui::Companion::create(std::move(devices[i]), options.companions[i], settings, (*own)[i]);
        if (!c)
            return c.error();
        companions.add(std::move(*c));
    }
    return companions;
}

// Whether the frame shown has the camera's image, or the source has none to give.
bool showsColour(ui::Presenter& presenter) {
    const auto& shown = presenter.shown();
    return !presenter.instrument().capabilities().color || (shown && !shown->frame->capturedImage.empty());
}

// A colour sensor may start later than the depth sensor, and on a busy machine the frames asked for can all
// come before its first image: the run goes on while Patience allows for one that has it, so camera.png
// shows the camera. Returns whether one came; says so when none did.
bool waitForColour(ui::Presenter& presenter, ui::Companions& companions, double timeSeconds) {
    Patience patience(presenter.instrument());
    while (!showsColour(presenter) && patience.keepWaiting()) {
        companions.update(presenter.settings(), timeSeconds);
        if (presenter.update(timeSeconds, std::chrono::milliseconds(50)))
            presented(presenter, companions);
        if (replayEnded(presenter.instrument()))
            break;
    }
    if (!showsColour(presenter))
        std::fprintf(
            stderr,
            "depthcloud: note: no frame with the camera's image arrived in %lld s; camera.png is not "
            "written\n",
            patience.secondsWaited());
    return showsColour(presenter);
}

} // namespace

int runHeadless(const ViewerOptions& options, std::unique_ptr<devices::Device> device,
                Devices companionDevices) {
    setLogQuiet(true);
    auto context = render::EglContext::createHeadless();
    if (!context)
        return commandFailed("", context.error().message);
    render::ViewRenderer renderer;
    if (Status s = renderer.init(); !s)
        return commandFailed("", s.error().message);
    engine::Instrument instrument(std::move(device), options.source);
    // Headless snapshots start from the defaults, never a user's saved view; --settings and --set choose.
    auto settings = chosenSettings({}, options);
    if (!settings)
        return commandFailed("", settings.error().message);
    ui::Presenter presenter(instrument, renderer, *settings);
    presenter.resizeCloud(kCloudWidth, kCloudHeight);
    auto companions = startCompanions(options, std::move(companionDevices), *settings);
    if (!companions)
        return commandFailed("", companions.error().message);
    presenter.setCompanions(&*companions);
    instrument.start();
    // A source that cannot start has said why already (the instrument logs it as an error, naming it).
    if (!instrument.status().running)
        return kExitFailure;

    const int frames = options.frames.value_or(60);
    int shown = 0;
    while (shown < frames) {
        if (waitForFrame(presenter, *companions, shown * kHeadlessFrameSeconds)) {
            presented(presenter, *companions);
            ++shown;
            continue;
        }
        if (replayEnded(instrument) && shown > 0) {
            std::fprintf(stderr,
                         "depthcloud: note: the recording ended after %d frames (--frames asked for %d)\n",
                         shown, frames);
            break;
        }
        const engine::InstrumentStatus s = instrument.status();
        return commandFailed("", "no frame from " + s.source + " for " +
                                     std::to_string(kFrameTimeout.count()) + " s" +
                                     (s.message.empty() ? "" : ": " + s.message));
    }
    if (!showsColour(presenter))
        (void)waitForColour(presenter, *companions, shown * kHeadlessFrameSeconds);
    if (Status s = waitForCompanions(presenter, *companions, shown * kHeadlessFrameSeconds); !s)
        return commandFailed("", s.error().message);
    auto written = presenter.savePanels(options.outDirectory);
    if (!written)
        return commandFailed("", written.error().message);
    auto companionFiles = companions->savePanels(options.outDirectory);
    if (!companionFiles)
        return commandFailed("", companionFiles.error().message);
    written->insert(written->end(), companionFiles->begin(), companionFiles->end());
    if (!companions->empty()) {
        if (Status s = presenter.writeFusedPly(options.outDirectory + "/cloud.ply"); !s)
            return commandFailed("", s.error().message);
        written->emplace_back("cloud.ply");
    }
    const std::string summary = summaryJson(presenter.summary(), context->rendererName(), "headless",
                                            companions->summaries(instrument, presenter.shown()));
    if (Status s = base::writeTextFile(options.outDirectory + "/summary.json", summary); !s)
        return commandFailed("", s.error().message);
    written->emplace_back("summary.json");
    std::string names;
    for (const std::string& name : *written)
        names += (names.empty() ? "" : " ") + name;
    std::printf("depthcloud: wrote %s to %s\n", names.c_str(), options.outDirectory.c_str());
    return kExitOk;
}

} // namespace dc::tool
