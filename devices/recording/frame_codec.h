#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "frame/frame.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dc::devices::recording {

enum class ColorStorage { AsCaptured, Jpeg };

// How frames are stored. Depth and confidence are always lossless; only JPEG color is lossy.
struct EncodeOptions {
    bool compress = true; // zstd on depth, confidence and raw color; false stores them as they are
    int zstdLevel = 1;    // 1 keeps up with 1280x720 at 30 fps on one core; higher is smaller and slower
    ColorStorage color = ColorStorage::AsCaptured;
    int jpegQuality = 90;
};

const char* toString(ColorStorage storage);

// What the description chunk holds: the recorded device as the replay shows it.
struct DeviceInfo {
    std::string description;
    Capabilities capabilities;
};

std::vector<std::uint8_t> encodeDescription(const DeviceInfo& info);
// Fields after the ones version 1.0 defines are ignored, so a newer minor version still opens.
std::optional<DeviceInfo> decodeDescription(std::span<const std::uint8_t> payload);

// The depth map as the integers it was made of, when every sample is exactly float(k * scale) for a
// 16-bit k at one of the scales importers use (millimetres; TUM's 1/5000 m): that stores half the bytes
// and decodes bit-exactly.
std::optional<double> exactUint16Scale(const frame::Plane<float>& depthMeters);
// The one conversion from integer depth units to meters, shared by importers and the decoder so that
// exactUint16Scale recognises what they produce.
inline float depthFromUnits(std::uint16_t units, double metersPerUnit) {
    return static_cast<float>(units * metersPerUnit);
}

// Serialises frames into chunk payloads. Keeps its compression context and scratch between frames;
// one encoder per thread.
class FrameEncoder {
public:
    explicit FrameEncoder(EncodeOptions options = {});
    ~FrameEncoder();
    FrameEncoder(FrameEncoder&&) noexcept;
    FrameEncoder& operator=(FrameEncoder&&) noexcept;

    Expected<std::vector<std::uint8_t>> encode(const frame::Frame& frame);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Parses frame payloads. Every size is checked against the payload before it is used; errors name the
// file, the frame and the byte offset.
class FrameDecoder {
public:
    FrameDecoder();
    ~FrameDecoder();
    FrameDecoder(FrameDecoder&&) noexcept;
    FrameDecoder& operator=(FrameDecoder&&) noexcept;

    Expected<frame::Frame> decode(std::span<const std::uint8_t> payload, std::uint64_t payloadOffset,
                                  const std::string& file, std::uint64_t frameIndex);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace dc::devices::recording
