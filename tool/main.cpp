// depthcloud: see a depth camera's data as a live point cloud with depth and confidence panels.

#include "base/log.h"
#include "devices/source_spec.h"
#include "devices/video/video_codec.h"
#include "tool/align_command.h"
#include "tool/bench_camera.h"
#include "tool/bench_engine.h"
#include "tool/bench_instrument.h"
#include "tool/bench_quality.h"
#include "tool/bench_registration.h"
#include "tool/bench_soak.h"
#include "tool/bench_upsample_options.h"
#include "tool/controls_command.h"
#include "tool/live_commands.h"
#include "tool/options.h"
#include "tool/quality_command.h"
#include "tool/recording_commands.h"
#include "tool/version.h"

#include <CLI/CLI.hpp>
#include <opencv2/core/utils/logger.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

namespace {

using namespace dc::tool;

bool hasDisplay() {
    const char* x = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x && *x) || (wayland && *wayland);
}

int badArgument(const std::string& message) {
    std::fprintf(stderr, "depthcloud: error: %s\n", message.c_str());
    return kExitBadArguments;
}

// A source that cannot open is a bad --source, except where depthcloud's own video module is missing: that
// is the installation's failure, not the argument's.
int sourceCannotOpen(const dc::Error& error) {
    if (!dc::devices::video::isVideoSupportMissing(error))
        return badArgument("--source: " + error.message);
    std::fprintf(stderr, "depthcloud: error: %s\n", error.message.c_str());
    return kExitFailure;
}

// Creates `dir` if needed and proves it is writable, so a long run does not fail at its very end.
std::string checkOutDirectory(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        return "--out " + dir + ": cannot create directory: " + ec.message();
    const std::string probe = dir + "/.depthcloud-write-test";
    FILE* f = std::fopen(probe.c_str(), "w");
    if (!f)
        return "--out " + dir + ": directory is not writable";
    std::fclose(f);
    std::remove(probe.c_str());
    return {};
}

void addViewerOptions(CLI::App& app, ViewerOptions& o, std::vector<std::string>& sources) {
    app.add_option("--source", sources,
                   std::string("depth source (default synthetic); given again, each further source joins the "
                               "first in one cloud, placed by its pose: ") +
                       dc::devices::kSourceSpecHelp);
    app.add_flag("--headless", o.headless,
                 "no window: render offscreen and write PNGs + summary.json to --out");
    app.add_option("--frames", o.frames,
                   "stop after N frames (headless default 60; a window goes on until the source's first "
                   "frame is shown, at most a minute)")
        ->check(CLI::Range(1, 1'000'000'000));
    app.add_option("--out", o.outDirectory, "output directory (headless default: depthcloud-snapshots)");
    // By name in help and errors: CLI11 would print a Confidence (a byte) as a raw control character.
    app.add_option_function<std::string>(
           "--confidence",
           [&o](const std::string& name) {
               static const std::map<std::string, dc::frame::Confidence> kLevels{
                   {"low", dc::frame::Confidence::Low},
                   {"medium", dc::frame::Confidence::Medium},
                   {"high", dc::frame::Confidence::High}};
               o.confidence = kLevels.at(name);
           },
           "lowest confidence drawn in the cloud")
        ->transform(CLI::IsMember({"low", "medium", "high"}, CLI::ignore_case));
    app.add_flag("--reset", o.reset, "start with default settings and layout");
    app.add_option("--settings", o.settingsPath,
                   "start from this settings file (the JSON the window saves) instead of the saved one");
    app.add_option(
        "--set", o.sets,
        "set one setting, SECTION.KEY=VALUE as named in the settings file (e.g. cloud.fillGaps=false); "
        "repeatable, applied after --settings; sourceN.processing.KEY=VALUE or "
        "sourceN.cloud.minConfidence=VALUE "
        "gives the Nth --source (from 2) its own");
}

int runViewer(ViewerOptions o, const std::vector<std::string>& sources) {
    if (!sources.empty()) {
        o.source = sources.front();
        o.companions.assign(sources.begin() + 1, sources.end());
    }
    auto device = dc::devices::openSourceSpec(o.source);
    if (!device)
        return sourceCannotOpen(device.error());
    dc::tool::Devices companions;
    for (const std::string& spec : o.companions) {
        auto companion = dc::devices::openSourceSpec(spec);
        if (!companion)
            return sourceCannotOpen(dc::Error{spec + ": " + companion.error().message});
        companions.push_back(std::move(*companion));
    }
    auto settings = chosenSettings({}, o);
    if (!settings)
        return badArgument(settings.error().message);
    if (auto own = furtherSourcesSettings(*settings, o); !own)
        return badArgument(own.error().message);
    if (!o.headless && !hasDisplay()) {
        dc::logInfo("no display found (DISPLAY and WAYLAND_DISPLAY are unset): running headless");
        o.headless = true;
    }
    if (o.headless && o.outDirectory.empty())
        o.outDirectory = "depthcloud-snapshots";
    if (!o.outDirectory.empty()) {
        if (const std::string problem = checkOutDirectory(o.outDirectory); !problem.empty())
            return badArgument(problem);
    }
    return o.headless ? runHeadless(o, std::move(*device), std::move(companions))
                      : runGui(o, std::move(*device), std::move(companions));
}

} // namespace

int main(int argc, char** argv) {
    // OpenCV's own warnings (an image file it cannot open, once per frame of a replay whose files vanished)
    // repeat what our messages say once, naming the file and what it was for.
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    CLI::App app{"depthcloud: a live, colored point cloud of what a depth camera measures, with depth and "
                 "confidence panels",
                 "depthcloud"};
    app.set_version_flag("--version", versionLine());
    ViewerOptions viewer;
    std::vector<std::string> viewerSources;
    addViewerOptions(app, viewer, viewerSources);

    BenchOptions bench;
    CLI::App* benchCmd = app.add_subcommand("bench", "measure performance");
    benchCmd->require_subcommand(1);
    CLI::App* benchRender = benchCmd->add_subcommand("render", "viewer frame time on this machine's GL");
    benchRender->add_option("--frames", bench.frames, "measured frames per case (at least 10)")
        ->check(CLI::Range(10, 100000))
        ->capture_default_str();
    benchRender->add_option("--source-fps", bench.sourceFps, "the rate frames arrive at, as from a camera")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    benchRender->add_option("--json", bench.jsonPath, "also write the results as JSON to this file");
    benchRender->add_flag("--breakdown", bench.breakdown,
                          "also time the GL points frame without each part of the default view (fill gaps, "
                          "the 2D panels together and one by one, the controls, decimation)");
    BenchInstrumentOptions benchInstrument;
    BenchCameraOptions benchCamera;
    CLI::App* benchCameraCmd = addBenchCameraCommand(*benchCmd, benchCamera);
    BenchEngineOptions benchEngine;
    CLI::App* benchEngineCmd = addBenchEngineCommand(*benchCmd, benchEngine);
    BenchSoakOptions benchSoak;
    CLI::App* benchSoakCmd = addBenchSoakCommand(*benchCmd, benchSoak);
    CLI::App* benchInstrumentCmd = addBenchInstrumentCommand(*benchCmd, benchInstrument);
    BenchCaptureOptions benchCapture;
    CLI::App* benchCaptureCmd = addBenchCaptureCommand(*benchCmd, benchCapture);
    BenchLatencyOptions benchLatency;
    CLI::App* benchLatencyCmd = addBenchLatencyCommand(*benchCmd, benchLatency);
    BenchQualityOptions benchQuality;
    CLI::App* benchQualityCmd = addBenchQualityCommand(*benchCmd, benchQuality);
    BenchRegistrationOptions benchRegistration;
    CLI::App* benchRegistrationCmd = addBenchRegistrationCommand(*benchCmd, benchRegistration);
    BenchUpsampleOptions benchUpsample;
    CLI::App* benchUpsampleCmd = addBenchUpsampleCommand(*benchCmd, benchUpsample);
    DevicesOptions devicesOptions;
    CLI::App* devicesCmd = addDevicesCommand(app, devicesOptions);
    ControlsOptions controlsOptions;
    CLI::App* controlsCmd = addControlsCommand(app, controlsOptions);
    QualityOptions qualityOptions;
    CLI::App* qualityCmd = addQualityCommand(app, qualityOptions);
    AlignOptions alignOptions;
    CLI::App* alignCmd = addAlignCommand(app, alignOptions);

    RecordingCommands recording;
    addRecordingCommands(app, *benchCmd, recording);

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) { // --help, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return badArgument(e.what());
    }
    if (auto code = runRecordingCommands(recording))
        return *code;
    if (benchRender->parsed())
        return runBenchRender(bench);
    if (benchCameraCmd->parsed())
        return runBenchCamera(benchCamera);
    if (benchEngineCmd->parsed())
        return runBenchEngine(benchEngine);
    if (benchSoakCmd->parsed())
        return runBenchSoak(benchSoak);
    if (benchInstrumentCmd->parsed())
        return runBenchInstrument(benchInstrument);
    if (benchCaptureCmd->parsed())
        return runBenchCapture(benchCapture);
    if (benchLatencyCmd->parsed())
        return runBenchLatency(benchLatency);
    if (benchQualityCmd->parsed())
        return runBenchQuality(benchQuality);
    if (benchRegistrationCmd->parsed())
        return runBenchRegistration(benchRegistration);
    if (benchUpsampleCmd->parsed())
        return runBenchUpsample(benchUpsample);
    if (devicesCmd->parsed())
        return runDevices(devicesOptions);
    if (controlsCmd->parsed())
        return runControls(controlsOptions);
    if (qualityCmd->parsed())
        return runQuality(qualityOptions);
    if (alignCmd->parsed())
        return runAlign(alignOptions);
    return runViewer(viewer, viewerSources);
}
