// The command line as a new user meets it: the binary run from a directory outside the repository (so no
// ../shared), bad arguments refused with exit code 2 and one line naming the argument, failures while
// running with exit code 1, help that prints names and agrees with the checks.

#include "tests/test_data.h"
#include "tool_in_temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

using dc::test::lines;
using dc::test::readFile;
using dc::test::RunResult;

class Cli : public dc::test::ToolInTempDir {
protected:
    RunResult run(const std::string& arguments) const { return runTool(arguments); }
};

bool printable(const std::string& text) {
    return std::all_of(text.begin(), text.end(), [](char c) {
        return c == '\n' || (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f);
    });
}

TEST_F(Cli, BadArgumentsExitWithTwoAndOneLineNamingTheArgument) {
    struct Case {
        const char* args;
        const char* mentions;
    };
    const Case cases[] = {
        {"--headless --source synthetic:99999x99999", "--source"},
        {"--headless --source synthetic:7680x7680", "limit of 2764800 pixels"},
        {"--headless --source v4l2:/dev/null", "v4l2:/dev/null: not a video capture node"},
        {"--headless --source synthetic:rig=stereo", "unknown rig 'stereo'"},
        {"--headless --confidence extreme", "--confidence: extreme not in {low,medium,high}"},
        {"--headless --frames 0", "--frames"},
        {"record --frames 0 a.dcrec", "--frames"},
        {"record --frames 1 missing/a.dcrec", "no such directory missing"},
        {"bench record --case nope", "--case"},
        {"bench replay --data nowhere", "--data"},
        {"--headless --set cloud.nosuch=1", "--set 'cloud.nosuch' is not a setting"},
        {"--headless --set cloud.path=9", "--set 'cloud.path' cannot be 9"},
        {"--headless --set cloud.path=pointz",
         "--set 'cloud.path' cannot be pointz (one of: automatic, points, splat)"},
        {"--headless --set cloud.fillGaps", "--set 'cloud.fillGaps': expected SECTION.KEY=VALUE"},
        {"--headless --settings nowhere.json", "--settings nowhere.json: cannot be read"},
        {"controls --source synthetic", "--source synthetic: controls need a live camera"},
        {"controls --source v4l2:", "--source"},
        {"controls", "--source is required"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.mentions), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << "once, on one line: " << c.args << "\n" << r.err;
    }
}

// A scripted run measures what a person configured: --settings (the file the window saves) and --set.
TEST_F(Cli, SettingsAndSetChooseWhatAHeadlessRunDraws) {
    const auto cloudPathOf = [&](const std::string& arguments) {
        const RunResult r = run("--headless --frames 2 --out out " + arguments);
        EXPECT_EQ(r.exitCode, 0) << arguments << "\n" << r.err;
        const std::string summary = readFile(dir_ / "out" / "summary.json");
        const auto at = summary.find("\"cloudPath\"");
        return at == std::string::npos ? std::string() : summary.substr(at, summary.find('\n', at) - at);
    };
    EXPECT_NE(cloudPathOf("").find("software GL"), std::string::npos)
        << "llvmpipe chooses the splat by itself";
    EXPECT_NE(cloudPathOf("--set cloud.path=1").find("GL points (chosen)"), std::string::npos);
    EXPECT_NE(cloudPathOf("--set cloud.path=points").find("GL points (chosen)"), std::string::npos)
        << "a choice by its name";
    { std::ofstream(dir_ / "points.json") << R"({"cloud": {"path": 1}})"; }
    EXPECT_NE(cloudPathOf("--settings points.json").find("GL points (chosen)"), std::string::npos);
    EXPECT_NE(cloudPathOf("--settings points.json --set cloud.path=Splat").find("CPU splat (chosen)"),
              std::string::npos)
        << "--set applies after --settings";
}

TEST_F(Cli, AnExistingRecordingIsABadArgumentAndStaysAsItWas) {
    std::ofstream(dir_ / "take.dcrec") << "an earlier take";
    const RunResult r = run("record --source synthetic:32x24 --frames 2 take.dcrec");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("take.dcrec already exists (pass --overwrite to replace it)"), std::string::npos);
    EXPECT_EQ(readFile(dir_ / "take.dcrec"), "an earlier take");
    EXPECT_FALSE(fs::exists(dir_ / "take.dcrec.partial"));
}

TEST_F(Cli, AFailureWhileRunningExitsWithOne) {
    // Well-formed ids of a camera that is not plugged in: nothing is wrong with the argument.
    const RunResult r = run("record --source usb:1234:5678 --frames 1 cam.dcrec");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("1234:5678"), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
}

TEST_F(Cli, ControlsOfACameraThatIsNotThereExitWithOneNamingIt) {
    const RunResult node = run("controls --source v4l2:/dev/video-none");
    EXPECT_EQ(node.exitCode, 1) << node.err;
    EXPECT_NE(node.err.find("/dev/video-none: cannot open"), std::string::npos) << node.err;
    EXPECT_EQ(lines(node.err), 1u) << node.err;
    const RunResult usb = run("controls --source usb:1234:5678 --set brightness=1");
    EXPECT_EQ(usb.exitCode, 1) << usb.err;
    EXPECT_NE(usb.err.find("no camera matches usb:1234:5678"), std::string::npos) << usb.err;
}

// A preset is checked before the camera is touched: one that is no preset, or a --save over a file that is
// there, is a bad argument, and the file stays as it was.
TEST_F(Cli, ControlsPresetsThatCannotBeUsedAreBadArgumentsBeforeTheCameraIsTouched) {
    std::ofstream(dir_ / "kept.json") << "an earlier preset";
    const RunResult save = run("controls --source v4l2:/dev/video-none --save kept.json");
    EXPECT_EQ(save.exitCode, 2) << save.err;
    EXPECT_NE(save.err.find("--save kept.json already exists (pass --overwrite to replace it)"),
              std::string::npos)
        << save.err;
    EXPECT_EQ(readFile(dir_ / "kept.json"), "an earlier preset");
    const RunResult notPreset = run("controls --source v4l2:/dev/video-none --load kept.json");
    EXPECT_EQ(notPreset.exitCode, 2) << notPreset.err;
    EXPECT_NE(notPreset.err.find("--load: kept.json: not JSON"), std::string::npos) << notPreset.err;
    std::ofstream(dir_ / "newer.json")
        << R"({"format": "depthcloud-controls-preset", "version": 9, "nodes": []})";
    const RunResult newer = run("controls --source v4l2:/dev/video-none --load newer.json");
    EXPECT_EQ(newer.exitCode, 2) << newer.err;
    EXPECT_NE(newer.err.find("newer.json: preset version 9 is newer"), std::string::npos) << newer.err;
    std::ofstream(dir_ / "bad.json")
        << R"({"format": "depthcloud-controls-preset", "version": 1, "nodes": [{"controls": [{"name": "gain", "value": 1.5}]}]})";
    const RunResult value = run("--headless --frames 1 --source v4l2:/dev/video-none:preset=bad.json");
    EXPECT_EQ(value.exitCode, 2) << value.err;
    EXPECT_NE(
        value.err.find("preset=bad.json in --source: bad.json: nodes[0].controls[0]: the value of 'gain'"),
        std::string::npos)
        << value.err;
    for (const RunResult* r : {&save, &notPreset, &newer, &value})
        EXPECT_EQ(lines(r->err), 1u) << r->err;
}

// A source that cannot start in a headless run says why once, naming the source (the instrument's error
// and the run's own were both printed).
TEST_F(Cli, ASourceThatCannotStartIsReportedOnceWithExitOne) {
    const RunResult r =
        run("--headless --frames 1 --source ros:/camera/depth:master=http://127.0.0.1:9 --out out");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("ROS"), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "summary.json"));
}

// Video (a Stray capture's rgb.mp4) is a module loaded on first use; DC_VIDEO_MODULE points the binary at
// a module that is not there, as on a system where it or one of its libraries is missing.
TEST_F(Cli, WithoutTheVideoModuleAStrayCaptureIsOneLineAndExitOne) {
    ASSERT_EQ(::setenv("DC_VIDEO_MODULE", (dir_ / "missing" / "depthcloud-video.so").c_str(), 1), 0);
    const RunResult replay =
        run("--headless --frames 1 --out out --source replay:" + dc::test::dataPath("arkit_dance_stray"));
    ASSERT_EQ(run("record --source synthetic:32x24 --frames 2 take.dcrec").exitCode, 0);
    const RunResult exported = run("export --source replay:take.dcrec --format stray --out stray");
    ::unsetenv("DC_VIDEO_MODULE");
    for (const RunResult* r : {&replay, &exported}) {
        EXPECT_EQ(r->exitCode, 1) << r->err;
        EXPECT_NE(r->err.find("video support not installed: "), std::string::npos) << r->err;
        EXPECT_NE(r->err.find("depthcloud-video.so"), std::string::npos) << "dlerror() names it: " << r->err;
        EXPECT_EQ(lines(r->err), 1u) << r->err;
    }
    EXPECT_FALSE(fs::exists(dir_ / "stray" / "rgb.mp4"));
}

// The shipped binary stays lean: image files go through libpng and TurboJPEG, video through the module, so
// neither OpenCV's imgcodecs (GDAL, OpenEXR, ...) nor its videoio (FFmpeg, GStreamer) is in its closure.
TEST_F(Cli, TheBinaryLoadsNeitherImgcodecsNorVideoio) {
    const std::string command =
        std::string("ldd ") + DEPTHCLOUD_BINARY + " > '" + (dir_ / "ldd.txt").string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0);
    const std::string libraries = readFile(dir_ / "ldd.txt");
    ASSERT_NE(libraries.find("libopencv_core"), std::string::npos) << libraries;
    for (const char* heavy :
         {"libopencv_imgcodecs", "libopencv_videoio", "libavcodec", "libgdal", "libgstreamer"})
        EXPECT_EQ(libraries.find(heavy), std::string::npos) << heavy << " is linked:\n" << libraries;
}

TEST_F(Cli, HelpPrintsConfidenceLevelsByName) {
    const RunResult r = run("--help");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.out.find("{low,medium,high}"), std::string::npos) << r.out;
    EXPECT_TRUE(printable(r.out)) << "no raw control bytes in --help";
}

TEST_F(Cli, BenchReplayRunsOnSyntheticDataOutsideTheRepository) {
    ASSERT_FALSE(fs::exists(dir_ / "../shared/data")) << "this test must run away from the checkout";
    const RunResult r = run("bench replay --passes 1 --synthetic-frames 10 --bag-frames 3");
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("synthetic 640x480 recording (zstd, NV12)        10 frames"), std::string::npos)
        << r.out;
    // The same frames through every format's writer and our reader, each read back whole.
    for (const char* format : {"as a ROS 1 bag", "as MCAP", "as a rosbag2 .db3"})
        EXPECT_NE(r.out.find(std::string("same frames ") + format), std::string::npos) << format << "\n"
                                                                                       << r.out;
    EXPECT_EQ(r.out.find("cannot write or open"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find(" failed)"), std::string::npos) << r.out;
}

} // namespace
