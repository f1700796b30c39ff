#pragma once

#include "devices/recording/recording_writer.h"
#include "frame/frame.h"

#include <filesystem>
#include <string>
#include <vector>

namespace dc::test {

// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string path(const std::string& name = {}) const {
        return name.empty() ? dir_.string() : (dir_ / name).string();
    }

private:
    std::filesystem::path dir_;
};

// `count` distinct frames of the moving synthetic camera (noisy depth, confidence, NV12 color, pose) at
// depth w x h, with timestamps 1/30 s apart from `firstTimestampNs`.
std::vector<frame::FramePtr> syntheticFrames(int count, int width = 32, int height = 24,
                                             std::int64_t firstTimestampNs = 1'000'000'000);

// Every camera metadata field, distinct per `n`, the SCR's USB frame at its 11-bit limit for n = 0.
frame::CameraMetadata fullCameraMetadata(std::uint32_t n);
// The frames again, each with driver timing as a UVC camera reports it: depth sequence numbers that wrap
// past 2^32 and skip one, sensor stamps, on even frames a colour stream with a source of its own, and
// camera metadata on odd frames (every field) and on frame 2 (the frame counter and SCR USB frame only).
std::vector<frame::FramePtr> withTiming(const std::vector<frame::FramePtr>& frames);
// Every field of the two timings is equal (a default FrameTiming when nothing was recorded).
void expectSameTiming(const frame::FrameTiming& a, const frame::FrameTiming& b);

// Writes the frames as a finished recording.
void writeRecording(const std::string& path, const std::vector<frame::FramePtr>& frames,
                    devices::recording::WriterOptions options = {});

std::vector<std::uint8_t> readBytes(const std::string& path);
void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes);

// Bitwise equality of two float planes (NaN payloads included).
bool sameBits(const frame::Plane<float>& a, const frame::Plane<float>& b);

} // namespace dc::test
