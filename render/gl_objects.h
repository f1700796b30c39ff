#pragma once

#include "base/expected.h"

#include <epoxy/gl.h>

#include <initializer_list>
#include <string_view>
#include <utility>

// Move-only owners of OpenGL object names, shaped like Magnum's GL objects: a default-constructed object
// holds no name (id 0) so renderers can hold members before a context exists, create() makes one, and the
// destructor deletes it. Every call that creates, deletes or uses one must run with a current context on
// the GL thread; destroying an empty object makes no GL call, so empty objects may outlive the context.
namespace dc::render::gl {

namespace detail {

void deleteTexture(GLuint id);
void deleteBuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteShader(GLuint id);
void deleteProgram(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteRenderbuffer(GLuint id);
void deleteQuery(GLuint id);

// One owned name. GL uses 0 as "no object" for every kind, so 0 is the empty state.
template <void (*Delete)(GLuint)> class UniqueName {
public:
    UniqueName() = default;
    explicit UniqueName(GLuint id) : id_(id) {}
    UniqueName(UniqueName&& other) noexcept : id_(other.release()) {}
    UniqueName& operator=(UniqueName&& other) noexcept {
        reset(other.release());
        return *this;
    }
    UniqueName(const UniqueName&) = delete;
    UniqueName& operator=(const UniqueName&) = delete;
    ~UniqueName() { reset(); }

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    [[nodiscard]] GLuint release() { return std::exchange(id_, 0); }
    void reset(GLuint id = 0) {
        if (id_ != 0)
            Delete(id_);
        id_ = id;
    }

private:
    GLuint id_ = 0;
};

} // namespace detail

class Texture : public detail::UniqueName<detail::deleteTexture> {
public:
    using UniqueName::UniqueName;
    static Texture create();
};

class Buffer : public detail::UniqueName<detail::deleteBuffer> {
public:
    using UniqueName::UniqueName;
    static Buffer create();
};

class VertexArray : public detail::UniqueName<detail::deleteVertexArray> {
public:
    using UniqueName::UniqueName;
    static VertexArray create();
};

class Framebuffer : public detail::UniqueName<detail::deleteFramebuffer> {
public:
    using UniqueName::UniqueName;
    static Framebuffer create();
};

class Renderbuffer : public detail::UniqueName<detail::deleteRenderbuffer> {
public:
    using UniqueName::UniqueName;
    static Renderbuffer create();
};

// A query object, e.g. GL_TIME_ELAPSED: the GPU's own time for the commands between begin and end.
class Query : public detail::UniqueName<detail::deleteQuery> {
public:
    using UniqueName::UniqueName;
    static Query create();
};

class Shader : public detail::UniqueName<detail::deleteShader> {
public:
    using UniqueName::UniqueName;
    // `stage` is GL_VERTEX_SHADER or GL_FRAGMENT_SHADER; a failure carries the driver's compile log.
    static Expected<Shader> compile(GLenum stage, std::string_view source);
};

class Program : public detail::UniqueName<detail::deleteProgram> {
public:
    using UniqueName::UniqueName;
    // A failure carries the driver's compile or link log.
    static Expected<Program> link(std::string_view vertexSource, std::string_view fragmentSource);
    // -1 when the program has no active uniform of that name; glUniform* ignores -1.
    GLint uniformLocation(const char* name) const;
};

// Binds `texture` as GL_TEXTURE_2D, creating it first when it is empty, with nearest filtering and edges
// clamped: a texture read with texelFetch ignores filtering but must still be complete, which the default
// minification filter (expecting mipmaps) would leave it not.
void bindNearestTexture(Texture& texture);

// Binds each texture to its unit (a 2D texture per unit) and leaves unit 0 active.
void bindTextureUnits(std::initializer_list<std::pair<GLint, GLuint>> unitsAndTextures);

// A vertex shader for three vertices without attributes: corners (-1, -1), (3, -1), (-1, 3), one triangle
// that covers the viewport with no diagonal seam. Passes that shade every pixel of a target draw it.
inline constexpr const char* kFullscreenVertexShader = R"glsl(#version 330 core
void main() {
    vec2 corner = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID >> 1) * 4 - 1));
    gl_Position = vec4(corner, 0.0, 1.0);
}
)glsl";

} // namespace dc::render::gl
