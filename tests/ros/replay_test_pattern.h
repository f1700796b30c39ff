#pragma once

// The frames the ROS test writers draw, bag (make_test_bags.py) and MCAP (tests/mcap/writer) alike: their
// layout and pixel formulas, so that a replayed frame is checked against what was written.

#include <array>
#include <cstddef>
#include <cstdint>

namespace dc::devices::ros::pattern {

constexpr std::size_t kFrames = 5;
constexpr int kDepthW = 64, kDepthH = 48, kColorW = 80, kColorH = 60;
constexpr std::int64_t kStartNs = 1000'000'000'000, kFrameNs = 33'333'333;

inline int depthUnits(int x, int y, std::size_t i) {
    return x + 100 * y + 1000 * static_cast<int>(i);
}

inline std::array<std::uint8_t, 3> colorRgb(int x, int y, std::size_t i) {
    const int n = static_cast<int>(i);
    return {static_cast<std::uint8_t>((3 * x + n) % 256), static_cast<std::uint8_t>((4 * y) % 256),
            static_cast<std::uint8_t>((7 * n + x + y) % 256)};
}

} // namespace dc::devices::ros::pattern
