#include "tool/recording_commands.h"

#include "devices/source_spec.h"
#include "exporting/export.h"

namespace dc::tool {

namespace {

void addRecord(CLI::App& app, RecordOptions& o, RecordingCommands& c) {
    c.recordCmd = app.add_subcommand("record", "record a source to a depthcloud recording (.dcrec)");
    c.recordCmd->add_option("--source", o.source, std::string("what to record: ") + devices::kSourceSpecHelp)
        ->capture_default_str();
    auto* frames = c.recordCmd->add_option("--frames", o.frames, "stop after N frames")
                       ->check(CLI::Range(1, 1'000'000'000));
    c.recordCmd->add_option("--seconds", o.seconds, "stop after S seconds")
        ->check(CLI::Range(0.001, 1e9))
        ->excludes(frames);
    c.recordCmd->add_flag("--overwrite", o.overwrite, "replace OUT if it exists");
    c.recordCmd->add_option("--color", o.color, "camera image: raw (as captured) or jpeg")
        ->check(CLI::IsMember({"raw", "jpeg"}))
        ->capture_default_str();
    c.recordCmd->add_option("--jpeg-quality", o.jpegQuality, "JPEG quality")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    c.recordCmd
        ->add_option("--compression", o.compression, "lossless compression of depth, confidence, raw color")
        ->check(CLI::IsMember({"zstd", "none"}))
        ->capture_default_str();
    c.recordCmd->add_option("--zstd-level", o.zstdLevel, "zstd level")
        ->check(CLI::Range(1, 19))
        ->capture_default_str();
    c.recordCmd->add_option("--queue", o.queueFrames, "frames the writer may fall behind before dropping")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.recordCmd->add_option("OUT", o.out, "the recording to write")->required();
}

void addExport(CLI::App& app, ExportOptionsCli& o, RecordingCommands& c) {
    c.exportCmd = app.add_subcommand(
        "export",
        "export a recording or capture as PLY clouds, Stray layout, depth PNGs or a ROS 2 MCAP file");
    c.exportCmd
        ->add_option("--source", o.sources,
                     "replay:PATH (a recording, Stray or TUM directory, a bag); given again (--format ply), "
                     "one PLY per frame of the first holds every source's points in the world frame: each "
                     "further source's frame nearest in time, placed by its pose= after its recorded pose")
        ->required();
    c.exportCmd->add_option("--out", o.out, "output directory (mcap: the .mcap file)")->required();
    c.exportCmd->add_option("--frames", o.frames, "frames A:B (B excluded; A: and :B too)");
    c.exportCmd
        ->add_option("--format", o.format,
                     "ply | stray | png16 | mcap (ROS 2 messages as the RealSense wrapper names them, zstd "
                     "chunks, indexed: depth 16UC1 in millimetres where every sample of a frame is a whole "
                     "millimetre, else 32FC1 in meters; colour rgb8; infrared mono8/mono16; camera_info; the "
                     "pose on /tf)")
        ->check(CLI::IsMember({"ply", "stray", "png16", "mcap"}))
        ->capture_default_str();
    c.exportCmd->add_flag("--overwrite", o.overwrite, "mcap: replace OUT if it exists");
    c.exportCmd->add_flag(
        "--world", o.world,
        "PLY points in world coordinates (through each frame's pose; always with several --source)");
    c.exportCmd
        ->add_option(
            "--upsample", o.upsample,
            "upsample each frame's depth to half the camera image first: none | fast (guided filter, "
            "s = 4) | full (guided filter) | global (global smoother, real time) | quality (global "
            "smoother, quality mode: hundreds of ms per frame)")
        ->check(CLI::IsMember({"none", "fast", "full", "global", "quality"}))
        ->capture_default_str();
}

} // namespace

void addRecordingCommands(CLI::App& app, CLI::App& bench, RecordingCommands& c) {
    addRecord(app, c.record, c);
    addExport(app, c.exportOptions, c);
    c.benchReplayCmd = bench.add_subcommand("replay", "replay decode throughput, headless");
    c.benchReplayCmd
        ->add_option("--data", c.benchReplay.data,
                     "also decode this capture (a recording, a Stray or TUM directory, e.g. "
                     "../shared/data/arkit_dance_stray)")
        ->check(CLI::ExistingPath);
    c.benchReplayCmd
        ->add_option("--synthetic-frames", c.benchReplay.syntheticFrames, "frames of the synthetic recording")
        ->check(CLI::Range(10, 10000))
        ->capture_default_str();
    c.benchReplayCmd
        ->add_option("--bag-frames", c.benchReplay.bagFrames,
                     "1280x720 frames for the comparison of recording, ROS bag, MCAP and .db3")
        ->check(CLI::Range(2, 3000));
    c.benchReplayCmd
        ->add_option("--passes", c.benchReplay.passes, "passes over every case; the median is reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.benchRecordCmd = bench.add_subcommand(
        "record", "recording throughput, drops and size (default: 1280x720 depth + color @30 fps)");
    c.benchRecordCmd->add_option("--seconds", c.benchRecord.seconds, "seconds per case")
        ->check(CLI::Range(1.0, 3600.0))
        ->capture_default_str();
    c.benchRecordCmd->add_option("--case", c.benchRecord.only, "run only this case")
        ->check(CLI::IsMember({"raw", "zstd1", "zstd3", "jpeg", "zstd1-1t", "jpeg-1t"}));
    c.benchRecordCmd
        ->add_option("--dir", c.benchRecord.directory, "where to write the recordings (removed after)")
        ->check(CLI::ExistingDirectory);
    c.benchRecordCmd
        ->add_option("--load", c.benchRecord.load, "processes that each keep one of the cores busy meanwhile")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    c.benchRecordCmd->add_option("--json", c.benchRecord.jsonPath,
                                 "also write the results as JSON to this file");
    c.benchRecordCmd
        ->add_option("--sync-ms", c.benchRecord.syncMs, "write-back interval in ms (0: only at close)")
        ->check(CLI::Range(0, 60000))
        ->capture_default_str();
    c.benchRecordCmd->add_option(
        "--source", c.benchRecord.source,
        "record the first frames of this source (as --source takes it) at its own rate");
    c.benchRecordCmd->add_option("--cores", c.benchRecord.cores, "run on this many CPUs (0: all)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
}

std::optional<int> runRecordingCommands(const RecordingCommands& c) {
    if (c.recordCmd->parsed())
        return runRecord(c.record);
    if (c.exportCmd->parsed())
        return runExport(c.exportOptions);
    if (c.benchReplayCmd->parsed())
        return runBenchReplay(c.benchReplay);
    if (c.benchRecordCmd->parsed())
        return runBenchRecord(c.benchRecord);
    return std::nullopt;
}

} // namespace dc::tool
