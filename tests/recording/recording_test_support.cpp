#include "tests/recording/recording_test_support.h"

#include "devices/synthetic/synthetic_device.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <unistd.h>

namespace dc::test {

TempDir::TempDir() {
    static int counter = 0;
    dir_ = std::filesystem::temp_directory_path() /
           ("depthcloud-recording-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
}

std::vector<frame::FramePtr> syntheticFrames(int count, int width, int height,
                                             std::int64_t firstTimestampNs) {
    devices::SyntheticConfig config;
    config.depthWidth = width;
    config.depthHeight = height;
    config.cameraWidth = 2 * width;
    config.cameraHeight = 2 * height;
    config.motion = true;
    config.paced = false;
    devices::SyntheticDevice device(config);
    EXPECT_TRUE(device.open());
    EXPECT_TRUE(device.start());
    std::vector<frame::FramePtr> frames;
    while (static_cast<int>(frames.size()) < count) {
        auto r = device.capture(std::chrono::seconds(1));
        if (r.kind != devices::CaptureResult::Kind::Frame)
            continue;
        auto f = std::make_shared<frame::Frame>(*r.frame);
        f->timestampNs = firstTimestampNs + static_cast<std::int64_t>(frames.size()) * 33'333'333;
        frames.push_back(std::move(f));
    }
    return frames;
}

frame::CameraMetadata fullCameraMetadata(std::uint32_t n) {
    return {.frameCounter = 4242 + n,
            .gain = 16 + n,
            .laserPowerMw = 150,
            .ptsTicks = 0x89ab'cdefu + n,
            .scrTicks = 0xfedc'ba98u,
            .scrUsbFrame = static_cast<std::uint16_t>(0x7ff - n)};
}

std::vector<frame::FramePtr> withTiming(const std::vector<frame::FramePtr>& frames) {
    std::vector<frame::FramePtr> timed;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        auto f = std::make_shared<frame::Frame>(*frames[i]);
        const auto n = static_cast<std::uint32_t>(i);
        f->timing.depth = {.driverSequence = 0xffff'fffeu + n + (i > 2 ? 1u : 0u),
                           .sensorNs = f->timestampNs - 4'000'000,
                           .source = frame::TimestampSource::StartOfExposure,
                           .monotonic = true,
                           .exposureUs = std::nullopt};
        if (i % 2 == 0)
            f->timing.colour = frame::StreamTiming{.driverSequence = i == 0 ? std::nullopt : std::optional(n),
                                                   .sensorNs = f->timestampNs + 2'500'001,
                                                   .source = frame::TimestampSource::EndOfFrame,
                                                   .monotonic = false,
                                                   .exposureUs = std::nullopt};
        if (i % 2 == 1)
            f->timing.depthMetadata = fullCameraMetadata(n);
        else if (i == 2) {
            f->timing.depthMetadata.frameCounter = 4242 + n;
            f->timing.depthMetadata.scrUsbFrame = 0x7ff;
        }
        timed.push_back(std::move(f));
    }
    return timed;
}

void expectSameTiming(const frame::FrameTiming& a, const frame::FrameTiming& b) {
    const auto same = [](const frame::StreamTiming& x, const frame::StreamTiming& y) {
        EXPECT_EQ(x.driverSequence, y.driverSequence);
        EXPECT_EQ(x.sensorNs, y.sensorNs);
        EXPECT_EQ(x.source, y.source);
        EXPECT_EQ(x.monotonic, y.monotonic);
        EXPECT_EQ(x.exposureUs, y.exposureUs);
    };
    same(a.depth, b.depth);
    EXPECT_EQ(a.depthMetadata.frameCounter, b.depthMetadata.frameCounter);
    EXPECT_EQ(a.depthMetadata.gain, b.depthMetadata.gain);
    EXPECT_EQ(a.depthMetadata.laserPowerMw, b.depthMetadata.laserPowerMw);
    EXPECT_EQ(a.depthMetadata.ptsTicks, b.depthMetadata.ptsTicks);
    EXPECT_EQ(a.depthMetadata.scrTicks, b.depthMetadata.scrTicks);
    EXPECT_EQ(a.depthMetadata.scrUsbFrame, b.depthMetadata.scrUsbFrame);
    ASSERT_EQ(a.colour.has_value(), b.colour.has_value());
    if (a.colour)
        same(*a.colour, *b.colour);
}

void writeRecording(const std::string& path, const std::vector<frame::FramePtr>& frames,
                    devices::recording::WriterOptions options) {
    auto writer = devices::recording::RecordingWriter::create(
        path, {"test camera", {.sceneDepth = true, .confidence = true, .color = true, .pose = true}},
        options);
    ASSERT_TRUE(writer) << writer.error().message;
    for (const auto& f : frames)
        ASSERT_TRUE(writer->append(*f));
    ASSERT_TRUE(writer->finish());
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

bool sameBits(const frame::Plane<float>& a, const frame::Plane<float>& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

} // namespace dc::test
