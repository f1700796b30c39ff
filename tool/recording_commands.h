#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

// depthcloud record / export / bench replay / bench record: headless commands on the recording format
// and the replay sources (no GL).
namespace dc::tool {

struct RecordOptions {
    std::string source = "synthetic";
    std::optional<int> frames;
    std::optional<double> seconds;
    bool overwrite = false;
    std::string color = "raw"; // raw (as captured) | jpeg
    int jpegQuality = 90;
    std::string compression = "zstd"; // zstd | none
    int zstdLevel = 1;
    int queueFrames = 30;
    std::string out;
};

struct ExportOptionsCli {
    // --source given again: each further source's points join the first's in one PLY per frame of the first
    std::vector<std::string> sources;
    std::string out;
    std::string frames; // "A:B"
    std::string format = "ply";
    bool world = false;
    std::string upsample = "none"; // none | fast | full | global | quality
    bool overwrite = false;        // mcap: replace an existing file
};

struct BenchReplayOptions {
    std::string
        data; // a capture to decode besides the synthetic recording (a .dcrec, Stray or TUM directory)
    int syntheticFrames = 150;
    int bagFrames = 60; // 1280x720 frames for the comparison of formats (benchReplayFormats)
    int passes = 5;     // decodes of every frame per case; the median pass is reported
};

struct BenchRecordOptions {
    double seconds = 10.0;
    std::string only;      // run one case by name
    std::string directory; // where the recordings are written (and removed); default: the temp dir
    int cores = 2;         // pin the process to this many CPUs (0: leave as is)
    int load = 0;          // processes that each keep one of those cores busy meanwhile
    int syncMs = 1000;     // the recorder's write-back interval (0: only at close)
    std::string jsonPath;  // also write the results as JSON here
    std::string source;    // record frames of this --source at its rate (default: synthetic 1280x720 @30 fps)
};

struct RecordingCommands {
    RecordOptions record;
    ExportOptionsCli exportOptions;
    BenchReplayOptions benchReplay;
    BenchRecordOptions benchRecord;
    CLI::App* recordCmd = nullptr;
    CLI::App* exportCmd = nullptr;
    CLI::App* benchReplayCmd = nullptr;
    CLI::App* benchRecordCmd = nullptr;
};

void addRecordingCommands(CLI::App& app, CLI::App& bench, RecordingCommands& commands);
// The exit code of whichever of these commands was parsed; empty when none was.
std::optional<int> runRecordingCommands(const RecordingCommands& commands);

int runRecord(const RecordOptions& options);
int runExport(const ExportOptionsCli& options);
int runBenchReplay(const BenchReplayOptions& options);
int runBenchRecord(const BenchRecordOptions& options);

} // namespace dc::tool
