#pragma once

namespace dc::render {

// The fragment shader of every point drawing: the colour the vertex shader chose, opaque.
inline constexpr const char* kPointColorFragmentShader = R"glsl(#version 330 core
in vec3 pointColor;
out vec4 fragColor;

void main() {
    fragColor = vec4(pointColor, 1.0);
}
)glsl";

} // namespace dc::render
