#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>
#include <optional>

// The test cameras' pixels, stamps and lens (publish_camera.py for ROS 1, publish_camera_dds for ROS 2):
// each image follows formulas of its frame index, recomputed by the tests from the image's stamp, so every
// frame that arrives is checked pixel for pixel.
namespace dc::test::camera {

constexpr std::int64_t kStartNs = 1000'000'000'000; // frame 0's stamp
constexpr std::int64_t kPeriodNs = 33'333'333;      // 30 Hz
// The lens at 64x48, scaled with the image.
constexpr double kFx = 50.5, kFy = 51.25, kCx = 31.5, kCy = 23.75;

inline std::uint16_t depthUnits(int x, int y, std::int64_t i) {
    return static_cast<std::uint16_t>(x % 100 + 100 * (y % 50) + 1000 * (i % 50) + 1);
}

inline std::array<std::uint8_t, 3> colorRgb(int x, int y, std::int64_t i) {
    const int n = static_cast<int>(i % 256);
    return {static_cast<std::uint8_t>((3 * x + n) % 256), static_cast<std::uint8_t>((4 * y) % 256),
            static_cast<std::uint8_t>((7 * n + x + y) % 256)};
}

// Which of the publisher's frames carries this stamp; none when it is not a stamp the publisher sent.
inline std::optional<std::int64_t> frameIndex(std::int64_t stampNs) {
    const std::int64_t offset = stampNs - kStartNs;
    const std::int64_t i = (offset + kPeriodNs / 2) / kPeriodNs;
    if (offset < 0 || std::llabs(offset - i * kPeriodNs) >= 2)
        return std::nullopt;
    return i;
}

} // namespace dc::test::camera
