#include "gl_test_support.h"

#include "render/gl_objects.h"

#include <utility>

namespace dc::render::test {
namespace {

using GlObjectsTest = GlTest;

TEST_F(GlObjectsTest, ContextIsDesktopGl33OrNewer) {
    EXPECT_TRUE(epoxy_is_desktop_gl());
    EXPECT_GE(epoxy_gl_version(), 33);
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_TRUE(noGlError());
}

TEST_F(GlObjectsTest, DefaultConstructedHoldsNoObject) {
    gl::Texture texture;
    gl::Program program;
    EXPECT_EQ(texture.id(), 0u);
    EXPECT_FALSE(program);
}

TEST_F(GlObjectsTest, MoveTransfersOwnershipAndDestructionDeletes) {
    GLuint id = 0;
    {
        gl::Texture original = gl::Texture::create();
        glBindTexture(GL_TEXTURE_2D, original.id()); // a name becomes an object at its first bind
        id = original.id();
        ASSERT_NE(id, 0u);
        gl::Texture moved = std::move(original);
        EXPECT_EQ(original.id(), 0u); // NOLINT(bugprone-use-after-move): the moved-from state is the point
        EXPECT_EQ(moved.id(), id);
        gl::Texture assigned;
        assigned = std::move(moved);
        EXPECT_EQ(assigned.id(), id);
        EXPECT_TRUE(glIsTexture(id));
    }
    EXPECT_FALSE(glIsTexture(id));
    EXPECT_TRUE(noGlError());
}

TEST_F(GlObjectsTest, ReleaseHandsOverTheName) {
    gl::Buffer buffer = gl::Buffer::create();
    const GLuint id = buffer.release();
    EXPECT_EQ(buffer.id(), 0u);
    glBindBuffer(GL_ARRAY_BUFFER, id);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    EXPECT_TRUE(glIsBuffer(id));
    glDeleteBuffers(1, &id);
    EXPECT_TRUE(noGlError());
}

TEST_F(GlObjectsTest, ProgramLinksAndFindsItsUniforms) {
    const Expected<gl::Program> program =
        gl::Program::link("#version 330 core\nuniform vec4 offset;\nvoid main() { gl_Position = offset; }\n",
                          "#version 330 core\nout vec4 color;\nvoid main() { color = vec4(1.0); }\n");
    ASSERT_TRUE(program.ok()) << program.error().message;
    EXPECT_GE(program->uniformLocation("offset"), 0);
    EXPECT_EQ(program->uniformLocation("missing"), -1);
    EXPECT_TRUE(noGlError());
}

TEST_F(GlObjectsTest, CompileErrorsCarryTheDriverLog) {
    const Expected<gl::Program> program =
        gl::Program::link("#version 330 core\nvoid main() { gl_Position = undeclared; }\n",
                          "#version 330 core\nout vec4 color;\nvoid main() { color = vec4(1.0); }\n");
    ASSERT_FALSE(program.ok());
    EXPECT_NE(program.error().message.find("vertex shader does not compile"), std::string::npos);
    EXPECT_NE(program.error().message.find("undeclared"), std::string::npos) << program.error().message;
    EXPECT_TRUE(noGlError());
}

TEST_F(GlObjectsTest, LinkErrorsCarryTheDriverLog) {
    // Each stage compiles, but the varying's type differs between them.
    const Expected<gl::Program> program =
        gl::Program::link("#version 330 core\nout vec2 mismatched;\nvoid main() { mismatched = vec2(0.0); "
                          "gl_Position = vec4(0.0); }\n",
                          "#version 330 core\nin vec3 mismatched;\nout vec4 color;\nvoid main() { color = "
                          "vec4(mismatched, 1.0); }\n");
    ASSERT_FALSE(program.ok());
    EXPECT_NE(program.error().message.find("does not link"), std::string::npos) << program.error().message;
    EXPECT_TRUE(noGlError());
}

TEST(EglContextTest, CreatesAHeadlessContextWithARenderer) {
    Expected<EglContext> context = EglContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    EXPECT_FALSE(context->rendererName().empty());
    EglContext moved = std::move(context).value();
    EXPECT_TRUE(moved.makeCurrent().ok());
    EXPECT_FALSE(moved.rendererName().empty());
}

} // namespace
} // namespace dc::render::test
