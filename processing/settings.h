#pragma once

#include <array>

namespace dc::processing {

// Which depth map the cloud, the depth panel, fog and aura show. Smoothed falls back to the raw
// sceneDepth when the frame has no smoothedSceneDepth, as ARKit's fog sample does
// (`frame.smoothedSceneDepth ?? frame.sceneDepth`).
enum class DepthSource { Raw, Smoothed };

// Temporal smoothing: an exponential average per pixel, in meters, that restarts where the depth jumps.
struct SmoothingParams {
    // Weight of the newest measurement (1 = no smoothing). At 0.4 frame-to-frame flicker drops ~3.2x and
    // the per-pixel temporal spread ~2x; a change smaller than jumpMeters reaches 64% within 2 frames.
    float alpha = 0.4f;
    // A change larger than this between the history and a new measurement is motion, not noise: the
    // history restarts at the new value, so moving edges do not smear.
    float jumpMeters = 0.10f;
    // Frames a pixel that loses its measurement keeps its last smoothed value (0 = holes show at once).
    int holeFrames = 3;

    bool operator==(const SmoothingParams&) const = default;
};

enum class UpsamplingMethod {
    Full,    // guided filter at the output resolution
    Fast,    // fast guided filter: coefficients at 1/subsample of the output resolution, then interpolated
    Global,  // dual-guided global smoother (global_smoother.h): real time, close to the best offline error
    Quality, // the global smoother with three sweeps per output pass instead of one: export and snapshots
};

enum class UpsamplingSize {
    HalfCamera, // 960x720 for a 1920x1440 camera, as the point-cloud sample's texture
    FullCamera,
};

// Guided upsampling of depth and confidence to (a fraction of) the camera image's size.
struct UpsamplingParams {
    UpsamplingMethod method = UpsamplingMethod::Fast;
    int subsample = 4; // Fast only: 2, 4 or 8
    UpsamplingSize size = UpsamplingSize::HalfCamera;
    int radiusPixels = 8; // window radius, in output pixels
    // Regulariser in squared guide intensity (the camera's luma scaled to [0, 1]); independent of depth
    // units. Larger: smoother depth that copies less image texture.
    float epsilon = 1e-3f;
    // Each window's linear model counts in inverse proportion to how badly it fits its depth (He's filter
    // gives every window the same weight): windows straddling a depth edge then hardly blur it, and
    // windows on one surface average noise over the whole radius. Off = He's guided filter.
    bool fitWeighted = true;
    // Residual spread (meters) below which a window counts as a good fit: about the sensor's noise.
    float fitNoiseMeters = 0.005f;
    // Global and Quality: the sensor's depth noise (standard deviation, meters). Depth steps well above it
    // stay sharp; differences below it are smoothed away as noise.
    float depthNoiseMeters = 0.005f;
    // Global and Quality: scales every smoothness weight. Over a region of uniform colour a sample's
    // influence spreads over about sqrt(smoothness) times as many pixels.
    float smoothness = 1.0f;

    bool operator==(const UpsamplingParams&) const = default;
};

// Fog (ARKit's "Creating a fog effect using scene depth"): the camera image mixed with a fog color in
// proportion to distance.
struct FogSettings {
    float fogMaxMeters = 4.0f;    // distance at which the fog is opaque
    float blurSigmaPixels = 5.0f; // Gaussian blur of the depth map, in its own pixels (the sample's sigma)
    std::array<float, 3> color{0.78f, 0.80f, 0.84f}; // linear RGB in [0, 1]
    // The sample's debug overlay: red mixed in with weight 1 - confidence / 2 (solid red at low, half at
    // medium, none at high confidence).
    bool confidenceOverlay = false;

    bool operator==(const FogSettings&) const = default;
};

enum class AuraMatte {
    NearestRegion, // the nearest region that stands out from its surroundings (AuraSettings)
    NearRange,     // everything between nearMeters and farMeters
};

// Aura (the "super saiyan" article): a glowing ring around the nearest subject.
struct AuraSettings {
    AuraMatte matte = AuraMatte::NearestRegion;
    float nearMeters = 0.2f; // NearRange
    float farMeters = 1.0f;  // NearRange
    // NearestRegion. The subject is the nearest region of the depth map that stands out from what surrounds
    // it: the pixels connected to a nearest point through depths below the depth at which they first touch
    // a region that began nearer (an apple ends where it meets the desk it rests on). It counts when it
    // reaches separationMeters behind its nearest point before that (the apple reaches 4 cm; a book lying
    // on the desk 1.5 cm: it barely rises from the desk), and when its front, what lies within
    // separationMeters of its nearest point, covers at least minSizeMeters squared (sensor speckle covers
    // far less) and stays clear of the image's border: a front at the border continues out of view
    // towards the camera, as the floor or the desk the camera looks down at. The matte ends
    // regionDepthMeters behind the subject's nearest point at most. No subject: no ring.
    float separationMeters = 0.03f;
    float minSizeMeters = 0.04f;
    float regionDepthMeters = 0.6f;
    int ringPixels = 15; // width of the dilation window that makes the ring, in output pixels
    // The blurs' sizes oscillate as the article's sin(frame / 3) at 60 frames per second.
    float pulseHz = 3.18f;
    float whiteGain = 1.0f;
    float yellowGain = 2.0f; // the article doubles the yellow layer

    bool operator==(const AuraSettings&) const = default;
};

} // namespace dc::processing
