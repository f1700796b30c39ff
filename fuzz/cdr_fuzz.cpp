// libFuzzer: the CDR decoders of ROS 2 messages (Image, CameraInfo, TFMessage, a header's stamp) on arbitrary
// bytes.

#include "devices/ros/cdr.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace dc::devices::ros;
    (void)decodeHeaderStampNs({data, size});
    (void)decodeImage({data, size});
    (void)decodeCameraInfo({data, size});
    (void)decodeTfMessage({data, size});
    return 0;
}
