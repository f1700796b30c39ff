#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace dc::devices::usb {

// A depth camera we know by its USB ids: what one depth unit is in meters, the depth sensor's horizontal
// field of view for when no calibration file is given, and the vendor controls it has beyond V4L2's.
struct KnownCamera {
    std::uint16_t vendorId = 0;
    std::optional<std::uint16_t> productId; // nullopt: every product of the vendor
    const char* name = "";
    float depthScaleMeters = 0.001f;
    double depthHorizontalFovDegrees = 0.0;
    // A RealSense D4xx: its emitter and laser power are reached only through the depth extension unit
    // (v4l2/xu_controls.h), which no other camera may be sent a request for.
    bool realsenseDepthXu = false;
};

std::span<const KnownCamera> knownCameras();
// The most specific entry for VID:PID (an exact product before a vendor-wide entry), or nullptr.
const KnownCamera* findKnownCamera(std::uint16_t vendorId, std::uint16_t productId);

// Used for a device that is not in the table: 16-bit UVC depth in millimeters is the common convention
// (RealSense, Orbbec, most ToF modules), and a 70 degree horizontal field of view is typical of them.
inline constexpr float kDefaultDepthScaleMeters = 0.001f;
inline constexpr double kDefaultHorizontalFovDegrees = 70.0;

} // namespace dc::devices::usb
