#pragma once

#include "frame/camera_model.h"
#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/point_colours.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace dc::processing {

// Where each sample of a depth map lands in the colour image of a two-sensor camera: unprojected with the
// depth lens, moved into the colour sensor's frame, projected with the colour lens. A sample the colour
// camera cannot see (outside its image, behind it, or hidden behind a nearer surface) has no pixel there.
struct Registration {
    static constexpr std::int32_t kUnseen = -1;
    int colourWidth = 0;
    int colourHeight = 0;
    // Per depth sample, row-major: y * colourWidth + x of the colour pixel nearest its projection, or
    // kUnseen (also for samples without depth).
    std::vector<std::int32_t> colourPixel;
    frame::Plane<std::uint8_t> seen; // the depth map's size: 1 where colourPixel is a pixel
};

// Registers `depth` (any resolution: the rig's depth intrinsics are scaled to it) into a colour image of
// colourWidth x colourHeight. Visibility is decided with a z-buffer in colour-image space in which each
// sample covers its footprint, so a nearer surface hides what lies behind it even where the colour image
// is finer than the depth map.
Registration registerDepth(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                           int colourWidth, int colourHeight);

// The depth map as the colour sensor would measure it, at colourWidth x colourHeight: for each colour pixel
// the depth along the colour sensor's own axis (meters) of the nearest sample covering it (each sample
// covers its footprint, as in registerDepth's z-buffer), 0 where none does. The input of overlays and of
// effects that work in the colour image.
frame::Plane<float> alignDepthToColour(const frame::Plane<float>& depth, const frame::RigCalibration& rig,
                                       int colourWidth, int colourHeight);

// Where the samples of a depth map land in a colour image of colourWidth x colourHeight, as registerDepth
// places them: both cameras at the maps' sizes, how far outside the image a sample still counts (it covers
// border pixels), the ideal normalised radius (squared) beyond which the colour lens polynomial no longer
// describes the image (evaluated far outside the field of view it folds back and would put a point from
// behind the camera's shoulder into the picture), and the half side of the square a sample covers in the
// colour image, which is this factor times z / zc (depth along each sensor's axis), at least half a pixel.
struct ColourProjection {
    frame::CameraModel depthCamera;
    frame::CameraModel colourCamera;
    frame::RigidTransform depthToColour;
    double marginPixels = 0.0;
    double maxRadius2 = 0.0;
    double halfPerDepthOverColourZ = 0.0;
};
ColourProjection colourProjection(const frame::RigCalibration& rig, const frame::Intrinsics& depthIntrinsics,
                                  int colourWidth, int colourHeight);

// Two samples of one surface that cover the same colour pixel differ in depth by the surface's slope over a
// depth pixel, plus sensor noise (about 2 cm at 4 m for the noisiest sensors we read): within this much they
// are the same surface, and the farther one is not hidden.
inline constexpr float kSameSurfaceMeters = 0.01f;
inline constexpr float kSameSurfacePerMeter = 0.02f;
inline float sameSurfaceMeters(float colourZ) {
    return kSameSurfaceMeters + kSameSurfacePerMeter * colourZ;
}

// Whether a shader can register this rig point by point in closed form: a pinhole depth camera (so the
// cloud's own unprojection is the registration's) and a colour lens applied forward. Others are registered
// on the CPU.
bool shaderRegistrable(const frame::RigCalibration& rig);

// Whether a shader colours the samples of a frame with this rig (null: a single camera) itself: one camera,
// or a rig it registers (shaderRegistrable). The engine then leaves camera colours and the overlays made
// from them to the GL path (engine::Demand::gpuCameraColours).
bool shaderCanColour(const frame::RigCalibration* rig);

// A rig that is really one camera: no rotation or translation between the sensors, the same lens, and
// depth intrinsics that are the colour intrinsics scaled. Colouring then takes the single-camera path.
bool isSingleCamera(const frame::RigCalibration& rig);

// The colour given to a point the colour camera does not see: a neutral mid-gray, never a guess.
inline constexpr std::uint8_t kUnseenGray = 128;

// Point colours with the mask of the points the colour camera sees.
struct PointColours {
    std::shared_ptr<const RgbImage> colours;
    // Null when every point is seen (one camera); else the depth map's size, 1 = seen.
    std::shared_ptr<const frame::Plane<std::uint8_t>> seen;
};

// The colours of a depth map's points for `frame`: the single-camera pointColours() when the frame has no
// rig (bit for bit today's colours), else each point coloured where registerDepth() puts it.
PointColours framePointColours(const frame::Frame& frame, const frame::Plane<float>& depth,
                               CameraColourTable& table);
// The same for a depth map whose intrinsics are given (a decimated map's cells sit at their centres, which
// scaling the rig's intrinsics to its size would not give).
PointColours framePointColours(const frame::Frame& frame, const frame::Plane<float>& depth,
                               const frame::Intrinsics& depthIntrinsics, CameraColourTable& table);

// Whether the colour camera sees sample (u, v) of `depth`, exactly as framePointColours decides it, for one
// sample (the hover readout of a cloud whose colours the GPU made): one projection of every sample, no
// colours. True for one camera.
bool sampleSeenByColour(const frame::Frame& frame, const frame::Plane<float>& depth,
                        const frame::Intrinsics& depthIntrinsics, int u, int v);

// The depth panel's colour overlay: each depth sample's colour, opaque where the colour camera sees it and
// fully transparent (alpha 0, black) where it does not. The point colours' gray stands for "unseen" in the
// cloud; over the depth panel it would read as a colour the camera saw.
RgbaImage seenColourOverlay(const PointColours& colours);

// The colour image seen from the depth sensor, at width x height of the depth map's view: each pixel takes
// the colour where the colour camera sees the depth sample nearest it (registerDepth on the depth map
// resampled nearest), kUnseenGray where it sees none. The guide of upsampling on a two-sensor frame; a
// frame without a rig gets its camera image resampled (pointColours).
RgbImage colourAlignedToDepth(const frame::Frame& frame, const frame::Plane<float>& depth, int width,
                              int height, CameraColourTable& table);

} // namespace dc::processing
