#pragma once

#include "devices/device.h"
#include "devices/frame_pacer.h"
#include "devices/synthetic/synthetic_scene.h"

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

namespace dc::devices {

struct SyntheticConfig {
    int depthWidth = 256; // LiDAR-like 256x192 at 60 Hz, as ARKit's sceneDepth
    int depthHeight = 192;
    double fps = 60.0;
    int cameraWidth = 1920;
    int cameraHeight = 1440;
    std::uint64_t seed = 1;
    bool motion = false; // slow camera sway with the true pose in every frame
    bool noise = true;   // false: depth is the exact ground truth, confidence all High
    bool paced = true;   // false: deliver frames as fast as they are generated (tests, benchmarks)
    // A two-sensor camera (syntheticRigCalibration()): depth from one sensor, colour from another 15 mm
    // away with its own field of view and lens; every frame carries the rig's calibration.
    bool rig = false;
    // Instead of the desk scene, a flat grey target filling the view (depth-quality measurements).
    std::optional<FlatTarget> flatTarget = std::nullopt;
    // The still camera moved from its usual place, in its own frame (OpenCV axes: x right, y down, z
    // forward): several cameras viewing the one scene from known places. Not with motion.
    std::optional<frame::RigidTransform> view = std::nullopt;
};

// The rig's native modes: 848x480 depth at 30 Hz, 1280x720 colour.
SyntheticConfig syntheticRigConfig();

// Limits that keep a typo from allocating gigabytes: the camera image up to 8K per side, the depth map no
// larger than the default camera image (a depth map is upsampled to the image, never beyond it), and at
// most 1000 fps. A configuration beyond them is refused before anything is allocated.
inline constexpr int kSyntheticMaxImageSide = 7680;
inline constexpr std::int64_t kSyntheticMaxDepthPixels = 1920 * 1440;
inline constexpr double kSyntheticMaxFps = 1000.0;
// Why `config` is outside those limits, naming the limit; success when it is within them.
Status checkSyntheticConfig(const SyntheticConfig& config);

// The built-in depth camera: frames of the SyntheticScene at a steady rate. Without motion the camera
// image never changes, so it is rendered once and shared by every frame. A frame depends only on its
// sequence number, so worker threads render the next few ahead while the capture thread only waits for
// the pacer and hands them out in order: rendering never delays the cadence unless it falls behind it.
class SyntheticDevice final : public Device {
public:
    explicit SyntheticDevice(SyntheticConfig config = {});
    ~SyntheticDevice() override;

    std::string description() const override;
    Capabilities capabilities() const override;
    void interruptCapture() override;
    const SyntheticConfig& config() const { return config_; }
    const SyntheticScene& scene() const { return scene_; }
    // The frame the device delivers at `timeSeconds` after its start, made on the caller's thread
    // (benchmarks and tests that need given poses without waiting for them). Needs open() when the scene
    // does not move: the shared image is rendered there.
    frame::FramePtr makeFrame(std::uint64_t sequence, double timeSeconds) const;

protected:
    Status doOpen() override;
    Status doStart() override;
    void doStop() override;
    CaptureResult doCapture(std::chrono::milliseconds timeout) override;

private:
    class RenderAhead;

    std::shared_ptr<frame::Frame> renderFrame(std::uint64_t sequence, double timeSeconds) const;
    frame::CapturedImage renderImage(const frame::Pose& depthPose) const;
    frame::Intrinsics depthIntrinsics() const;
    frame::Pose poseAt(double timeSeconds) const;

    SyntheticConfig config_;
    SyntheticScene scene_;
    frame::Intrinsics cameraIntrinsics_;
    std::shared_ptr<const frame::RigCalibration> rig_; // config_.rig only
    LensCamera colourCamera_;                          // the rig's colour sensor, its lens inverted once
    frame::CapturedImage staticImage_;
    FramePacer pacer_;
    std::uint64_t sequence_ = 0;
    std::unique_ptr<RenderAhead> renderAhead_; // while streaming
    std::shared_ptr<frame::Frame> pending_;    // rendered, waiting for its beat
};

} // namespace dc::devices
