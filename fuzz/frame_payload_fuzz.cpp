// libFuzzer: the frame decoder on arbitrary chunk payloads (sections, sizes, zstd, JPEG, layouts).

#include "devices/recording/frame_codec.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static dc::devices::recording::FrameDecoder decoder;
    (void)decoder.decode({data, size}, 72, "fuzz.dcrec", 0);
    return 0;
}
