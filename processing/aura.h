#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/settings.h"

#include <cstdint>

namespace dc::processing {

// The subject the aura surrounds, 1 inside and 0 outside, at the depth map's resolution (or at most 256
// pixels wide, nearest-sampled, for upsampled maps: the ring is made at 240 pixels wide anyway). NearRange:
// measured depths within [nearMeters, farMeters]. NearestRegion: the nearest region that stands out from
// what surrounds it (AuraSettings says how), all 0 when none does. `intrinsics` are the depth map's (any
// resolution of the same camera); they give the pixels' physical size.
frame::Plane<std::uint8_t> subjectMatte(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                        const AuraSettings& settings);

// The "super saiyan" aura: the matte dilated by a ringPixels-wide square window (separable) minus the matte
// itself is a ring; a small tent blur of it adds white, a large one yellow (twice as strong), their sizes
// oscillating over time as the article's, and both are added to the camera color.
//
// The image has half the camera image's size (960x720 for 1920x1440, the article's half-resolution matte);
// matte, ring and blurs work at a quarter of that (240x180), since the ring is 15 and the blurs 31 to 301
// output pixels wide and the result is blurred anyway; the sizes in AuraSettings are in output pixels. Empty
// without a camera image; the camera image without depth.
RgbaImage renderAura(const frame::Frame& frame, const AuraSettings& settings, DepthSource source,
                     double timeSeconds);
// The same from a camera image already at the output size, the depth that makes the matte (null: none) and
// that depth's camera intrinsics.
RgbaImage renderAura(const RgbImage& cameraImage, const frame::DepthData* depth,
                     const frame::Intrinsics& depthIntrinsics, const AuraSettings& settings,
                     double timeSeconds);

} // namespace dc::processing
