// libFuzzer: the metadata node's parsers (V4L2_META_FMT_UVC and V4L2_META_FMT_D4XX) on arbitrary buffers.

#include "devices/uvc/v4l2/uvc_metadata.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)dc::devices::v4l2::parseUvcMetadata({data, size});
    (void)dc::devices::v4l2::parseD4xxMetadata({data, size});
    return 0;
}
