#pragma once

#include <array>
#include <string>

namespace dc::render {

// The classic MATLAB "jet" colormap: dark blue at 0, then blue, cyan, yellow, red, and dark red at 1.
// Each channel is a trapezoid of slope 4 centred a quarter apart, which is why the ends are half bright.
// `normalised` is clamped to [0, 1]; NaN maps like 0.
std::array<float, 3> jetColor(float normalised);

// The depth panel's colormaps. Jet is the Depth Cloud sample's; turbo keeps jet's contrast without its
// false bands; viridis is perceptually uniform and survives colour blindness and grayscale printing.
enum class Colormap { Jet, Turbo, Viridis, Grayscale };
inline constexpr int kColormapCount = 4;
const char* toString(Colormap colormap);

// Every colormap is piecewise linear over this many evenly spaced stops, on the CPU and in GLSL alike, so
// the legend, the tests and the shader agree to rounding. Jet's breakpoints sit on multiples of 1/8, so
// jet is reproduced exactly.
inline constexpr int kColormapStopCount = 17;
using ColormapStops = std::array<std::array<float, 3>, kColormapStopCount>;
const ColormapStops& colormapStops(Colormap colormap);
// `normalised` is clamped to [0, 1]; NaN maps like 0.
std::array<float, 3> colormapColor(Colormap colormap, float normalised);

// GLSL for shaders: `colormapStops[17]`, the stops of `colormap` as constants, and
// `vec3 colormapColor(float normalised)`, the same interpolation as the C++ function. A program per
// colormap rather than a uniform array: Mesa's llvmpipe was seen to draw with a uniform array's previous
// contents now and then after it had been updated, which painted a depth panel in the wrong colormap.
std::string colormapGlsl(Colormap colormap);

} // namespace dc::render
