#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/settings.h"

namespace dc::processing {

// ARKit's fog sample on the CPU. The fog amount is the shown depth (see shownDepth) over fogMaxMeters,
// clamped to [0, 1] and blurred with a Gaussian of blurSigmaPixels (the sample blurs the depth; blurring the
// clamped amount differs only beyond fogMax, where both are 1); it mixes the camera color towards the fog
// color. With confidenceOverlay the result is then mixed towards red with weight 1 - confidence / 2, as the
// sample's confidenceDebugVisualization. A pixel without a measurement is beyond the sensor's range and
// counts as fully fogged, not as the 0 m its stored depth would say.
//
// The image has half the camera image's size (960x720 for 1920x1440, halfCameraSize): fog is soft, and this
// keeps it to a few milliseconds on two cores. Empty when the frame has no camera image; the plain camera
// image when it has no depth.
RgbaImage renderFog(const frame::Frame& frame, const FogSettings& settings, DepthSource source);
// The same from a camera image already at the output size (the engine converts it once for fog and aura)
// and the depth to fog with (null: none).
RgbaImage renderFog(const RgbImage& cameraImage, const frame::DepthData* depth, const FogSettings& settings);

} // namespace dc::processing
