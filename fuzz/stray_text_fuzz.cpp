// libFuzzer: the Stray Scanner text parsers (camera_matrix.csv, odometry.csv) on arbitrary text.

#include "devices/replay/stray_format.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    (void)dc::devices::replay::parseStrayCameraMatrix(text, "camera_matrix.csv");
    (void)dc::devices::replay::parseStrayOdometry(text, "odometry.csv");
    return 0;
}
