// libFuzzer: the TUM RGB-D list and ground-truth parsers and the timestamp association on arbitrary text.

#include "devices/replay/tum_format.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace dc::devices::replay;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    (void)parseTumGroundTruth(text, "groundtruth.txt");
    auto list = parseTumList(text, "rgb.txt");
    if (!list)
        return 0;
    // Associate the list with itself shifted by 10 ms: every branch of the greedy matching gets work.
    std::vector<double> a, b;
    for (const TumListEntry& e : *list) {
        a.push_back(e.timestampSeconds);
        b.push_back(e.timestampSeconds + 0.01);
    }
    (void)associateByTimestamp(a, b, 0.02);
    return 0;
}
