// libFuzzer: the MCAP reader on arbitrary bytes (footer, summary, chunk and message indexes, the pass over
// the data section, zstd and lz4 chunks), then the first messages of every channel through the CDR decoders.

#include "devices/ros/cdr.h"
#include "devices/ros/mcap_reader.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace dc::devices::ros;
    auto reader = McapReader::fromBytes({data, size}, "fuzz.mcap");
    if (!reader)
        return 0;
    for (const McapChannel& channel : (*reader)->channels()) {
        const std::size_t messages = std::min<std::size_t>((*reader)->messageCount(channel.id), 8);
        for (std::size_t i = 0; i < messages; ++i)
            if (auto message = (*reader)->message(channel.id, i)) {
                (void)decodeImage(*message);
                (void)decodeCameraInfo(*message);
                (void)decodeTfMessage(*message);
            }
    }
    return 0;
}
