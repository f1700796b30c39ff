#include "render/colormap.h"

#include <algorithm>
#include <cmath>

namespace dc::render {

namespace {

// One channel: 1 within 1/8 of `centre`, falling linearly to 0 at 3/8 from it.
float trapezoid(float t, float centre) {
    return std::clamp(1.5f - std::abs(4.0f * (t - centre)), 0.0f, 1.0f);
}

} // namespace

std::array<float, 3> jetColor(float normalised) {
    const float t = normalised > 0.0f ? std::min(normalised, 1.0f) : 0.0f;
    return {trapezoid(t, 0.75f), trapezoid(t, 0.5f), trapezoid(t, 0.25f)};
}

const char* const kJetColorGlsl = R"glsl(
vec3 jetColor(float normalised) {
    float t = clamp(normalised, 0.0, 1.0);
    vec3 centres = vec3(0.75, 0.5, 0.25);
    return clamp(1.5 - abs(4.0 * (t - centres)), 0.0, 1.0);
}
)glsl";

} // namespace dc::render
