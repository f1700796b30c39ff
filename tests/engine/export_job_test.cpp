// An export runs on a thread of its own: an exception thrown inside it is the job's result, the files
// written before it stay, and the process goes on. A fused export pairs frames as the window does.

#include "devices/recording/recording_writer.h"
#include "devices/replay/replay_device.h"
#include "engine/export_job.h"
#include "engine/replay_follow.h"
#include "engine_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <unistd.h>
#include <vector>

namespace dc::engine::test {
namespace {

namespace fs = std::filesystem;

TEST(ExportJob, AnExceptionInsideTheExportIsTheJobsResultAndTheFramesBeforeItStay) {
    const fs::path dir = fs::temp_directory_path() / ("dc-export-job-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string path = (dir / "take.dcrec").string();
    {
        auto writer = devices::recording::RecordingWriter::create(
            path, {"test camera", {.sceneDepth = true, .confidence = true}}, {});
        ASSERT_TRUE(writer) << writer.error().message;
        for (const frame::FramePtr& f : syntheticFrames(4))
            ASSERT_TRUE(writer->append(*f));
        ASSERT_TRUE(writer->finish());
    }
    exporting::ExportOptions options;
    options.format = exporting::ExportFormat::Png16;
    options.outDirectory = (dir / "out").string();
    int transformed = 0; // the seam: the processing of the second frame throws, as OpenCV can
    options.transform = [&transformed](frame::Frame f) {
        if (++transformed == 2)
            throw std::runtime_error("upsampling ran out of memory");
        return f;
    };

    auto job = ExportJob::start("replay:" + path, options);
    ASSERT_TRUE(job) << job.error().message;
    (*job)->join();
    EXPECT_TRUE((*job)->finished());
    const auto result = (*job)->result();
    ASSERT_TRUE(result.has_value());
    ASSERT_FALSE(result->ok());
    EXPECT_EQ(result->error().message, "export failed: upsampling ran out of memory");
    EXPECT_TRUE(fs::exists(dir / "out" / "depth" / "000000.png")) << "the frame before the fault";
    EXPECT_FALSE(fs::exists(dir / "out" / "depth" / "000001.png"));
    fs::remove_all(dir);
}

// The pairing a fused export shares with the window: a frame of the first recording is the same instant on
// a recording that overlaps it in time, else the same time since each one's first frame; the frame paired
// is the nearest, the earlier of two as near.
TEST(FusedExport, PairsOnTheCommonClockWithTheNearestFrame) {
    const RecordingSpan first{1'000, 2'000};
    EXPECT_EQ(onCompanionClock(first, 1'500, RecordingSpan{1'900, 5'000}), 1'500);
    EXPECT_EQ(onCompanionClock(first, 1'500, RecordingSpan{500, 1'000}), 1'500);
    EXPECT_EQ(onCompanionClock(first, 1'500, RecordingSpan{9'000, 9'900}), 9'500);
    EXPECT_EQ(onCompanionClock(first, 1'500, RecordingSpan{0, 999}), 500);

    const std::vector<std::int64_t> timestamps{100, 200, 300};
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 0), 0u);
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 149), 0u);
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 150), 0u);
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 151), 1u);
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 200), 1u);
    EXPECT_EQ(devices::replay::nearestTimeIndex(timestamps, 10'000), 2u);
    EXPECT_EQ(devices::replay::nearestTimeIndex({}, 10), 0u);
}

} // namespace
} // namespace dc::engine::test
