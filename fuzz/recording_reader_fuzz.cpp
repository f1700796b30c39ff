// libFuzzer: the recording reader on arbitrary bytes (header, trailer, index, chunk scan, every frame).
// Built with FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, so checksums do not stop mutated inputs.

#include "devices/recording/recording_reader.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto reader = dc::devices::recording::RecordingReader::fromBytes({data, size}, "fuzz.dcrec");
    if (!reader)
        return 0;
    const std::size_t frames = std::min<std::size_t>(reader->frameCount(), 16);
    for (std::size_t i = 0; i < frames; ++i)
        (void)reader->frame(i);
    return 0;
}
