#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/depth_quality.h"

#include <array>
#include <cstdint>
#include <span>

// Per-pixel maps of the depth-quality region (issue 29): where on the target the error is, not only how
// much. Each map is the region's size, in its own unit, NaN where the pixel has no value.
namespace dc::processing {

enum class QualityMap : std::uint8_t { None, PlaneResidual, TemporalStd, FillOverWindow };
inline constexpr QualityMap kQualityMaps[] = {QualityMap::None, QualityMap::PlaneResidual,
                                              QualityMap::TemporalStd, QualityMap::FillOverWindow};
const char* toString(QualityMap map); // "none", "plane residual", ...
const char* unitOf(QualityMap map);   // "mm", "mm", "%"

// Each valid sample's signed perpendicular distance to `plane`, mm (positive: behind the plane, away from
// the camera); NaN where `causes` says the sample is not valid. `causes` are the region's (classifySamples).
frame::Plane<float> planeResidualMm(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                                    const Roi& roi, std::span<const SampleCause> causes,
                                    const PlaneModel& plane);

// A map ready to show: its values, the range its colours span, and the picture.
struct QualityMapImage {
    QualityMap kind = QualityMap::None;
    frame::Plane<float> values;
    float low = 0.0f;  // the value of the ramp's first colour
    float high = 0.0f; // and of its last
    RgbaImage image;   // transparent where a value is NaN
};

// The colour at t in [0, 1] of the ramp a map is drawn with: a plane residual on a diverging ramp (blue,
// white at 0, red), the others on a sequential one (dark blue through green to yellow).
std::array<std::uint8_t, 3> mapColour(QualityMap kind, float t);

// `values` coloured for `kind`. The range: a residual symmetric about 0 out to the 98th percentile of its
// magnitude; a temporal deviation from 0 to its 98th percentile; the fill from 0 to 100 %. A map without a
// finite value gets the range [0, 1] and a transparent picture.
QualityMapImage colourMap(QualityMap kind, frame::Plane<float> values);

} // namespace dc::processing
