#pragma once

#include <array>

namespace dc::render {

// The classic MATLAB "jet" colormap: dark blue at 0, then blue, cyan, yellow, red, and dark red at 1.
// Each channel is a trapezoid of slope 4 centred a quarter apart, which is why the ends are half bright.
// `normalised` is clamped to [0, 1]; NaN maps like 0.
std::array<float, 3> jetColor(float normalised);

// The same function in GLSL, `vec3 jetColor(float normalised)`, for shaders to include. It lives next to
// the C++ version so the two cannot drift apart unnoticed; the gl tests compare them pixel by pixel.
extern const char* const kJetColorGlsl;

} // namespace dc::render
