#pragma once

#include "frame/camera_model.h"
#include "frame/frame.h"

#include <array>
#include <cstdint>
#include <vector>

namespace dc::devices {

// The scene's layout in meters. World axes are right-handed with y up (the desk top is the plane y = 0);
// the camera at rest looks along +z, so +x is on its left and the book, at positive x, lies left of the
// apple in the image. Public so that tests can compute the analytic ground truth independently of the ray
// caster.
namespace scene {
constexpr double kCameraHeight = 0.5;
constexpr double kCameraPitchDegrees = 20.0; // looking down at the desk
constexpr double kAppleCenter[3] = {-0.06, 0.045, 0.72};
constexpr double kAppleRadius = 0.045;
constexpr double kDeskHalfWidth = 0.7, kDeskNear = 0.2, kDeskFar = 1.4;
constexpr double kFloorY = -0.75;
constexpr double kWallZ = 1.9;
constexpr double kWindowMinX = -0.35, kWindowMaxX = 0.45, kWindowBottom = 0.3, kWindowTop = 1.1;
constexpr double kBlindsZ = 1.86, kBlindsBottom = 0.7, kSlatPitch = 0.05, kSlatHeight = 0.03;
constexpr double kBookMin[3] = {0.16, 0.0, 0.55}, kBookMax[3] = {0.38, 0.04, 0.85};
} // namespace scene

// A two-sensor RGB-D camera modelled on the RealSense D435's: a wide depth sensor (848x480, about 87 x 57
// degrees, no distortion) and, 15 mm to its right and turned by a few tenths of a degree, a narrower colour
// sensor (1280x720, about 69 x 42 degrees) with a lens distortion like a webcam's. Exact by construction, so
// it is the test bed for registration.
frame::RigCalibration syntheticRigCalibration();

// The colour sensor's camera-to-world pose when the depth sensor's is `depthPose`.
frame::Pose colourSensorPose(const frame::Pose& depthPose, const frame::RigidTransform& depthToColour);

// The exact registration of one depth map, straight from the scene's geometry: for each depth pixel
// (row-major) the colour-image position of the surface point it sees, and whether the colour camera sees that
// very point (inside its image and not hidden by anything nearer to it).
struct RegistrationTruth {
    std::vector<std::array<double, 2>> colourPixel; // NaN where the depth pixel sees nothing in range
    std::vector<std::uint8_t> visible;
};

// A flat target filling the view, as a depth-quality bench points a camera at a wall: the plane's distance
// along the optical axis, its turn about the camera's vertical (y) axis, and the standard deviation of the
// depth noise (along z, independent per sample and per frame).
struct FlatTarget {
    double distanceMeters = 1.0;
    double tiltDegrees = 0.0;
    double noiseMm = 1.0;
    bool operator==(const FlatTarget&) const = default;
};
// Limits of a flat target: within the sensor's range, and turned short of edge-on.
inline constexpr double kFlatTargetMaxTiltDegrees = 85.0;
inline constexpr double kFlatTargetMaxNoiseMm = 100.0;

// The flat target's depth for one frame: the exact plane plus Gaussian noise (none when noiseMm is 0, or
// `noise` is false), deterministic in (seed, sequence); 0 where the plane lies beyond
// SyntheticScene::kMaxRangeMeters or behind the camera. Confidence is High wherever there is depth.
frame::DepthData flatTargetDepth(const frame::Intrinsics& k, const FlatTarget& target, bool noise,
                                 std::uint64_t seed, std::uint64_t sequence);

// A camera and where each of its pixels looks through its lens (the undistorted normalised coordinates,
// row-major; empty without a lens). Inverting a lens is iterative, most of a frame's rendering through one:
// a camera that renders many frames inverts it once.
struct LensCamera {
    frame::CameraModel camera;
    std::vector<std::array<double, 2>> directions;
};
LensCamera lensCamera(const frame::CameraModel& camera);

// A deterministic procedural scene modelled on the Depth Cloud sample's figure: a desk with an
// apple-sized sphere and a book on it, a back wall with a window whose opening looks out beyond the
// sensor's range (no depth), half-open blinds in the window, and a floor. World axes: y up, meters.
//
// It is the embedded default source and the ground truth for tests: trueDepth() is the exact noise-free
// depth for any intrinsics, sensorDepth() adds a LiDAR-like noise model and the confidence derived from it.
class SyntheticScene {
public:
    static constexpr double kMaxRangeMeters = 5.0; // like the LiDAR Scanner: nothing beyond is measured

    explicit SyntheticScene(std::uint64_t seed = 1) : seed_(seed) {}

    // The default capturedImage intrinsics (ARKit-like 1920x1440, ~67 degrees horizontal field of view),
    // scaled to the requested image size.
    static frame::Intrinsics cameraIntrinsics(int width = 1920, int height = 1440);
    // Camera-to-world pose at time t, a rigid transform (its rotation has determinant +1). Without motion
    // the camera is fixed; with motion it sways slowly sideways and turns to keep the apple in view,
    // revealing the scene's depth.
    static frame::Pose cameraPose(double timeSeconds, bool motion);

    // Exact depth along the camera's z axis (meters), 0 where nothing is within kMaxRangeMeters.
    frame::Plane<float> trueDepth(const frame::Intrinsics& intrinsics, const frame::Pose& pose) const;
    // The same through a lens: each pixel's undistorted ray.
    frame::Plane<float> trueDepth(const frame::CameraModel& camera, const frame::Pose& pose) const;
    // Depth as a sensor would measure it: noise growing with distance and grazing angle, mixed pixels at
    // depth edges, and confidence (0/1/2) derived from that noise. Deterministic in (seed, sequence).
    frame::DepthData sensorDepth(const frame::Intrinsics& intrinsics, const frame::Pose& pose,
                                 std::uint64_t sequence) const;
    // The shaded, textured camera image as NV12 (full-range BT.601), consistent with the geometry.
    frame::CapturedImage renderImage(const frame::Intrinsics& intrinsics, const frame::Pose& pose) const;
    // The image through a lens: each pixel shows what its undistorted ray meets.
    frame::CapturedImage renderImage(const frame::CameraModel& camera, const frame::Pose& pose) const;
    // The same through a camera whose lens was inverted once.
    frame::CapturedImage renderImage(const LensCamera& camera, const frame::Pose& pose) const;
    // The registration truth for a depth map of depthCamera (at its intrinsics' size) into colourCamera's
    // image, for the depth sensor at depthPose.
    RegistrationTruth registrationTruth(const frame::CameraModel& depthCamera,
                                        const frame::CameraModel& colourCamera,
                                        const frame::RigidTransform& depthToColour,
                                        const frame::Pose& depthPose) const;

private:
    std::uint64_t seed_;
};

} // namespace dc::devices
