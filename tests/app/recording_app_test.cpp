// depthcloud record / export / replay as a user runs them, including a recorder killed with SIGKILL.

#include "devices/recording/recording_reader.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using dc::devices::recording::RecordingReader;

struct RunResult {
    int exitCode = -1;
    std::string output;
};

RunResult run(const std::string& arguments) {
    static int counter = 0;
    const fs::path log = fs::temp_directory_path() / ("depthcloud-rec-app-" + std::to_string(::getpid()) +
                                                      "-" + std::to_string(counter++) + ".log");
    const int status = std::system(
        (std::string(DEPTHCLOUD_BINARY) + " " + arguments + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    fs::remove(log);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

class RecordingApp : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("depthcloud-rec-app-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

TEST_F(RecordingApp, RecordsExportsAndReplaysThroughTheViewer) {
    const RunResult rec = run("record --source synthetic:64x48@60:motion --frames 20 " + path("a.dcrec"));
    ASSERT_EQ(rec.exitCode, 0) << rec.output;
    EXPECT_NE(rec.output.find("wrote 20 frames"), std::string::npos) << rec.output;
    auto reader = RecordingReader::open(path("a.dcrec"));
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(reader->frameCount(), 20u);
    EXPECT_TRUE(reader->openedThroughIndex());

    const RunResult exported = run("export --source replay:" + path("a.dcrec") + " --out " + path("ply") +
                                   " --format ply --frames 5:8");
    ASSERT_EQ(exported.exitCode, 0) << exported.output;
    EXPECT_NE(exported.output.find("100% 3/3 frames"), std::string::npos) << "progress bar on stderr";
    for (const char* name : {"000005.ply", "000006.ply", "000007.ply"})
        EXPECT_TRUE(fs::exists(path("ply/") + name)) << name;

    const RunResult viewer =
        run("--headless --frames 5 --source replay:" + path("a.dcrec") + " --out " + path("snap"));
    ASSERT_EQ(viewer.exitCode, 0) << viewer.output;
    EXPECT_TRUE(fs::exists(path("snap/cloud.png")));

    // Asking for more frames than the recording has: the run ends with a note at the recording's end
    // (frames replaced in the latest-wins mailbox by a slow consumer are not shown, so at most 20).
    const RunResult beyond =
        run("--headless --frames 50 --source replay:" + path("a.dcrec") + " --out " + path("all"));
    ASSERT_EQ(beyond.exitCode, 0) << beyond.output;
    std::smatch ended;
    ASSERT_TRUE(
        std::regex_search(beyond.output, ended, std::regex("the recording ended after ([0-9]+) frames")))
        << beyond.output;
    EXPECT_LE(std::stoi(ended[1]), 20);
    std::ifstream summary(path("all/summary.json"));
    const std::string text{std::istreambuf_iterator<char>(summary), {}};
    EXPECT_NE(text.find("\"frames\": " + ended[1].str() + ","), std::string::npos) << text;
    EXPECT_NE(text.find("\"latencyMs\": null"), std::string::npos) << "a recording's clock gives no latency";
}

TEST_F(RecordingApp, RefusesToOverwriteUnlessAsked) {
    ASSERT_EQ(run("record --source synthetic:32x24@60 --frames 3 " + path("o.dcrec")).exitCode, 0);
    const RunResult again = run("record --source synthetic:32x24@60 --frames 3 " + path("o.dcrec"));
    EXPECT_EQ(again.exitCode, 2) << "a bad argument";
    EXPECT_NE(again.output.find("o.dcrec already exists (pass --overwrite to replace it)"), std::string::npos)
        << again.output;
    EXPECT_EQ(run("record --overwrite --source synthetic:32x24@60 --frames 3 " + path("o.dcrec")).exitCode,
              0);
}

TEST_F(RecordingApp, KilledRecorderLeavesAReplayablePrefix) {
    const std::string out = path("k.dcrec");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, 1);
        ::dup2(devnull, 2);
        ::execl(DEPTHCLOUD_BINARY, DEPTHCLOUD_BINARY, "record", "--source", "synthetic:64x48@60:motion",
                "--seconds", "120", out.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    // Wait until the growing file holds at least 40 frames, then kill the recorder without warning.
    std::size_t framesBeforeKill = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (framesBeforeKill < 40 && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (auto partial = RecordingReader::open(out + ".partial"))
            framesBeforeKill = partial->frameCount();
    }
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the recorder must die by SIGKILL";
    ASSERT_GE(framesBeforeKill, 40u) << "the recorder never wrote 40 frames";

    EXPECT_FALSE(fs::exists(out)) << "an unfinished recording is never renamed into place";
    auto reader = RecordingReader::open(out + ".partial");
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_FALSE(reader->openedThroughIndex());
    ASSERT_GE(reader->frameCount(), framesBeforeKill) << "every frame seen before the kill is recovered";
    for (std::size_t i = 0; i < reader->frameCount(); ++i) {
        auto f = reader->frame(i);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(f->sceneDepth->depthMeters.width, 64);
        if (i > 0) {
            EXPECT_GT(f->timestampNs, reader->timestampNs(i - 1));
        }
    }
    const RunResult exported =
        run("export --source replay:" + out + ".partial --out " + path("png") + " --format png16");
    ASSERT_EQ(exported.exitCode, 0) << exported.output;
    EXPECT_NE(exported.output.find("wrote " + std::to_string(reader->frameCount()) + " frames"),
              std::string::npos)
        << exported.output;
    // The viewer opens the source once: the recovery's warning is printed once, not once per open.
    const RunResult viewed =
        run("--headless --source replay:" + out + ".partial --frames 2 --out " + path("snapshots"));
    ASSERT_EQ(viewed.exitCode, 0) << viewed.output;
    const std::string recovering = "recovering by scanning chunks";
    const auto first = viewed.output.find(recovering);
    ASSERT_NE(first, std::string::npos) << viewed.output;
    EXPECT_EQ(viewed.output.find(recovering, first + 1), std::string::npos) << viewed.output;
    const RunResult refused = run("record --source synthetic --frames 2 " + out);
    // The destination is refused before the source opens, like an existing output: a bad argument.
    EXPECT_EQ(refused.exitCode, 2) << "the interrupted recording is kept, not overwritten";
    EXPECT_EQ(RecordingReader::open(out + ".partial")->frameCount(), reader->frameCount());
    EXPECT_NE(refused.output.find("interrupted recording"), std::string::npos) << refused.output;
}

TEST_F(RecordingApp, BadInputsGetAClearErrorAndNoCrash) {
    std::ofstream(path("garbage.dcrec")) << "definitely not a recording, but long enough for a header";
    const RunResult garbage = run("export --source replay:" + path("garbage.dcrec") + " --out " + path("x"));
    EXPECT_EQ(garbage.exitCode, 2) << garbage.output;
    EXPECT_NE(garbage.output.find("garbage.dcrec: not a depthcloud recording (wrong magic at byte offset 0)"),
              std::string::npos)
        << garbage.output;
    const RunResult missing = run("--headless --source replay:" + path("nothing"));
    EXPECT_EQ(missing.exitCode, 2) << missing.output;
    EXPECT_NE(missing.output.find("nothing does not exist"), std::string::npos) << missing.output;
    const RunResult range = run("export --source replay:" + dc::test::dataPath("arkit_dance_stray") +
                                " --out " + path("y") + " --format png16 --frames 620:700");
    EXPECT_EQ(range.exitCode, 2) << range.output;
    EXPECT_NE(range.output.find("ends after the last frame (the source has 626 frames)"), std::string::npos)
        << range.output;
}

} // namespace
