#include "devices/uvc/usb/known_cameras.h"

#include <array>

namespace dc::devices::usb {

namespace {

// Depth units and fields of view from the vendors' datasheets. RealSense D4xx report depth in units of
// 1 mm by default and L515 in 0.25 mm; Orbbec UVC depth modules in 1 mm.
constexpr std::array kCameras{
    KnownCamera{0x8086, 0x0ad3, "Intel RealSense D415", 0.001f, 65.0, true},
    KnownCamera{0x8086, 0x0b07, "Intel RealSense D435", 0.001f, 87.0, true},
    KnownCamera{0x8086, 0x0b3a, "Intel RealSense D435i", 0.001f, 87.0, true},
    KnownCamera{0x8086, 0x0b5b, "Intel RealSense D405", 0.0001f, 87.0, true},
    KnownCamera{0x8086, 0x0b5c, "Intel RealSense D455", 0.001f, 87.0, true},
    KnownCamera{0x8086, 0x0b64, "Intel RealSense L515", 0.00025f, 70.0},
    KnownCamera{0x2bc5, std::nullopt, "Orbbec depth camera", 0.001f, 75.0},
};

} // namespace

std::span<const KnownCamera> knownCameras() {
    return kCameras;
}

const KnownCamera* findKnownCamera(std::uint16_t vendorId, std::uint16_t productId) {
    const KnownCamera* vendorWide = nullptr;
    for (const KnownCamera& camera : kCameras) {
        if (camera.vendorId != vendorId)
            continue;
        if (camera.productId == productId)
            return &camera;
        if (!camera.productId)
            vendorWide = &camera;
    }
    return vendorWide;
}

} // namespace dc::devices::usb
