// `depthcloud bench camera` as a user runs it: the figures it reports add up, and its own count of frames
// that reached the screen agrees with the instrument's.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

// `depthcloud bench camera ARGUMENTS --json FILE`'s JSON (discarded when the run fails or writes none).
nlohmann::json benchJson(const std::string& arguments) {
    const fs::path json =
        fs::temp_directory_path() / ("dc-bench-camera-" + std::to_string(::getpid()) + ".json");
    const std::string command = std::string(DEPTHCLOUD_BINARY) + " bench camera " + arguments + " --json " +
                                json.string() + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(json);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    fs::remove(json);
    return j;
}

TEST(BenchCamera, EveryDeliveredFrameIsShownDroppedOrInFlightAndBothCountsAgree) {
    const nlohmann::json j = benchJson("--seconds 2 --case 'ARKit 256x192 + camera 1920x1440'");
    ASSERT_FALSE(j.is_discarded());
    ASSERT_EQ(j["cases"].size(), 1u);
    const nlohmann::json& c = j["cases"][0];
    const auto n = [&](const char* key) { return c[key].get<long long>(); };
    // 2 s at 30 fps, give or take the edges of the window.
    EXPECT_GE(n("delivered"), 50);
    EXPECT_LE(n("delivered"), 70);
    // In flight is what is left over, never negative: the sum fails only if a frame is counted twice, and
    // the bound fails if frames go missing.
    EXPECT_EQ(n("shown") + n("droppedBeforeProcessing") + n("droppedBeforeDisplay") + n("inFlightAtEnd"),
              n("delivered"));
    EXPECT_LE(n("inFlightAtEnd"), 3) << "a frame or two on their way when the window closed";
    EXPECT_GT(n("shown"), 0);
    // The instrument counts over the same time, but a frame delivered just before the window opened and
    // shown inside it is the instrument's and not the bench's: at most a frame or two apart.
    EXPECT_LE(std::llabs(n("shown") - n("shownByInstrument")), 2);
    EXPECT_EQ(c["latencyMs"]["samples"].get<long long>(), n("shown")) << "one latency per frame shown";
    EXPECT_GT(c["latencyMs"]["median"].get<double>(), 0.0);
    EXPECT_LE(c["latencyMs"]["median"].get<double>(), c["latencyMs"]["p99"].get<double>());
    EXPECT_GT(c["glThreadCpuMsPerFrameDrawn"]["median"].get<double>(), 0.0);
    EXPECT_GT(c["bareGlPointsMs"].get<double>(), 0.0);
    EXPECT_EQ(n("samples"), 256 * 192);
}

// Two cameras fused in one cloud: the second camera's frames are counted on their own, and add up.
TEST(BenchCamera, ThePairsSecondCameraCountsItsOwnFrames) {
    const nlohmann::json j = benchJson("--seconds 2 --fps 10 --case 'two 848x480 + colour 1280x720, fused'");
    ASSERT_FALSE(j.is_discarded());
    const nlohmann::json& second = j["cases"][0]["secondCamera"];
    const auto n = [&](const char* key) { return second[key].get<long long>(); };
    // 2 s at 10 fps, give or take the edges of the window: the second camera's own rate, not the sum.
    EXPECT_GE(n("delivered"), 15) << second;
    EXPECT_LE(n("delivered"), 25) << second;
    EXPECT_LE(n("shown") + n("dropped"), n("delivered")) << second;
    EXPECT_GE(n("shown") + n("dropped") + 3, n("delivered")) << "a frame or two on their way at the end";
    EXPECT_GT(n("shown"), 0);
    EXPECT_GE(j["cases"][0]["delivered"].get<long long>(), 15) << "the first camera's count is its own";
    EXPECT_LE(j["cases"][0]["delivered"].get<long long>(), 25);
}

// Two cameras accumulating into one world cloud: the cloud holds more points than one camera's frame has
// samples (both cameras' frames, over time), and the frames replaced before the worker took them are a
// part of those the two cameras delivered.
TEST(BenchCamera, ThePairAccumulatingGathersBothCamerasFrames) {
    const nlohmann::json j =
        benchJson("--seconds 2 --fps 10 --case 'two 848x480 + colour 1280x720, fused, accumulating'");
    ASSERT_FALSE(j.is_discarded());
    const nlohmann::json& c = j["cases"][0];
    ASSERT_TRUE(c.contains("accumulationSkipped")) << c;
    EXPECT_GT(c["points"].get<long long>(), c["samples"].get<long long>()) << c;
    EXPECT_LE(c["accumulationSkipped"].get<long long>(),
              c["delivered"].get<long long>() + c["secondCamera"]["delivered"].get<long long>());
}

TEST(BenchCamera, AnUnknownCaseIsRefusedWithExitCode2) {
    const std::string command =
        std::string(DEPTHCLOUD_BINARY) + " bench camera --case nonsense > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
}

} // namespace
