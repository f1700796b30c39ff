#include "render/accumulated_points.h"

#include "render/point_shaders.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstddef>

namespace dc::render {

namespace {

constexpr const char* kVertexShader = R"glsl(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec4 color;
uniform mat4 worldToClip;
uniform float pointSizePixels;
out vec3 pointColor;

void main() {
    gl_Position = worldToClip * vec4(position, 1.0);
    gl_PointSize = pointSizePixels;
    pointColor = color.rgb;
}
)glsl";

} // namespace

Status AccumulatedPoints::init() {
    Expected<gl::Program> program = gl::Program::link(kVertexShader, kPointColorFragmentShader);
    if (!program)
        return Error{"accumulated points shaders: " + program.error().message};
    program_ = std::move(program).value();
    worldToClip_ = program_.uniformLocation("worldToClip");
    pointSize_ = program_.uniformLocation("pointSizePixels");
    vertexArray_ = gl::VertexArray::create();
    buffer_ = gl::Buffer::create();
    glBindVertexArray(vertexArray_.id());
    glBindBuffer(GL_ARRAY_BUFFER, buffer_.id());
    constexpr auto kStride = static_cast<GLsizei>(sizeof(processing::WorldPoint));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, kStride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, kStride,
                          reinterpret_cast<const void*>(offsetof(processing::WorldPoint, rgba)));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return Status::success();
}

void AccumulatedPoints::sync(processing::PointAccumulator& accumulator) {
    if (!buffer_)
        return;
    constexpr std::size_t kSize = sizeof(processing::WorldPoint);
    const auto& slots = accumulator.slots();
    glBindBuffer(GL_ARRAY_BUFFER, buffer_.id());
    if (accumulator.generation() != generation_ || slots.size() != capacity_) {
        // A new budget, a clear or a new CPU copy: start over from everything the accumulator holds.
        capacity_ = slots.size();
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capacity_ * kSize), slots.data(),
                     GL_DYNAMIC_DRAW);
        generation_ = accumulator.generation();
        cpu_ = keepCpu_ ? slots : std::vector<processing::WorldPoint>{};
        (void)accumulator.takeDirty();
        ++version_;
    }
    for (const auto& [begin, end] : accumulator.takeDirty()) {
        glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(begin * kSize),
                        static_cast<GLsizeiptr>((end - begin) * kSize), &slots[begin]);
        if (keepCpu_)
            std::copy(slots.begin() + static_cast<std::ptrdiff_t>(begin),
                      slots.begin() + static_cast<std::ptrdiff_t>(end),
                      cpu_.begin() + static_cast<std::ptrdiff_t>(begin));
        ++version_;
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    count_ = accumulator.size();
}

void AccumulatedPoints::setCpuCopy(bool keep) {
    if (keep == keepCpu_)
        return;
    keepCpu_ = keep;
    generation_ = ~0ull; // the next sync starts over, copying everything
}

void AccumulatedPoints::draw(const glm::mat4& worldToClip, float pointSizePixels) const {
    if (!program_ || count_ == 0)
        return;
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(program_.id());
    glUniformMatrix4fv(worldToClip_, 1, GL_FALSE, glm::value_ptr(worldToClip));
    glUniform1f(pointSize_, pointSizePixels);
    glBindVertexArray(vertexArray_.id());
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count_));
}

} // namespace dc::render
