#include "render/gl_objects.h"

#include <string>

namespace dc::render::gl {

namespace detail {

void deleteTexture(GLuint id) {
    glDeleteTextures(1, &id);
}
void deleteBuffer(GLuint id) {
    glDeleteBuffers(1, &id);
}
void deleteVertexArray(GLuint id) {
    glDeleteVertexArrays(1, &id);
}
void deleteShader(GLuint id) {
    glDeleteShader(id);
}
void deleteProgram(GLuint id) {
    glDeleteProgram(id);
}
void deleteFramebuffer(GLuint id) {
    glDeleteFramebuffers(1, &id);
}
void deleteRenderbuffer(GLuint id) {
    glDeleteRenderbuffers(1, &id);
}
void deleteQuery(GLuint id) {
    glDeleteQueries(1, &id);
}

} // namespace detail

namespace {

// glGen* only reserves a name; the object itself comes into existence at its first bind.
template <class Object> Object generate(void (*gen)(GLsizei, GLuint*)) {
    GLuint id = 0;
    gen(1, &id);
    return Object(id);
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    return log.c_str(); // drops the terminator GL wrote into the buffer
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    return log.c_str();
}

const char* stageName(GLenum stage) {
    switch (stage) {
    case GL_VERTEX_SHADER:
        return "vertex";
    case GL_FRAGMENT_SHADER:
        return "fragment";
    default:
        return "unknown";
    }
}

} // namespace

Texture Texture::create() {
    return generate<Texture>(glGenTextures);
}
Buffer Buffer::create() {
    return generate<Buffer>(glGenBuffers);
}
VertexArray VertexArray::create() {
    return generate<VertexArray>(glGenVertexArrays);
}
Framebuffer Framebuffer::create() {
    return generate<Framebuffer>(glGenFramebuffers);
}
Renderbuffer Renderbuffer::create() {
    return generate<Renderbuffer>(glGenRenderbuffers);
}

Query Query::create() {
    return generate<Query>(glGenQueries);
}

Expected<Shader> Shader::compile(GLenum stage, std::string_view source) {
    Shader shader(glCreateShader(stage));
    if (!shader)
        return Error{std::string("cannot create a ") + stageName(stage) + " shader"};
    const GLchar* text = source.data();
    const auto length = static_cast<GLint>(source.size());
    glShaderSource(shader.id(), 1, &text, &length);
    glCompileShader(shader.id());
    GLint compiled = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE)
        return Error{std::string(stageName(stage)) + " shader does not compile: " + shaderLog(shader.id())};
    return shader;
}

Expected<Program> Program::link(std::string_view vertexSource, std::string_view fragmentSource) {
    Expected<Shader> vertex = Shader::compile(GL_VERTEX_SHADER, vertexSource);
    if (!vertex)
        return vertex.error();
    Expected<Shader> fragment = Shader::compile(GL_FRAGMENT_SHADER, fragmentSource);
    if (!fragment)
        return fragment.error();
    Program program(glCreateProgram());
    if (!program)
        return Error{"cannot create a shader program"};
    glAttachShader(program.id(), vertex->id());
    glAttachShader(program.id(), fragment->id());
    glLinkProgram(program.id());
    // Detached shaders are deleted with their owners at the end of this scope; the program keeps the code.
    glDetachShader(program.id(), vertex->id());
    glDetachShader(program.id(), fragment->id());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE)
        return Error{"shader program does not link: " + programLog(program.id())};
    return program;
}

GLint Program::uniformLocation(const char* name) const {
    return glGetUniformLocation(id(), name);
}

void bindNearestTexture(Texture& texture) {
    if (texture) {
        glBindTexture(GL_TEXTURE_2D, texture.id());
        return;
    }
    texture = Texture::create();
    glBindTexture(GL_TEXTURE_2D, texture.id());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void bindTextureUnits(std::initializer_list<std::pair<GLint, GLuint>> unitsAndTextures) {
    for (const auto& [unit, texture] : unitsAndTextures) {
        glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
        glBindTexture(GL_TEXTURE_2D, texture);
    }
    glActiveTexture(GL_TEXTURE0);
}

} // namespace dc::render::gl
