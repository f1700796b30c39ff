#include "gl_test_support.h"

#include "render/render_target.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

namespace dc::render::test {
namespace {

using RenderTargetTest = GlTest;

// Fills the target's top half red and bottom half blue, in GL's bottom-up window coordinates.
void drawTopRedBottomBlue(const RenderTarget& target) {
    target.bind();
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, target.width(), target.height() / 2);
    glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glScissor(0, target.height() / 2, target.width(), target.height() - target.height() / 2);
    glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

TEST_F(RenderTargetTest, HoldsNothingUntilSized) {
    RenderTarget target;
    EXPECT_TRUE(target.empty());
    EXPECT_EQ(target.colorTexture(), 0u);
    EXPECT_TRUE(target.readRgba().empty());
    EXPECT_FALSE(target.savePng("/tmp/never-written.png").ok());
    EXPECT_FALSE(target.resize(0, 4).ok());
    EXPECT_FALSE(target.resize(4, -1).ok());
    EXPECT_TRUE(noGlError());
}

TEST_F(RenderTargetTest, ReadRgbaReturnsTheTopRowFirst) {
    RenderTarget target;
    ASSERT_TRUE(
        target.resize(5, 4).ok()); // an odd width: rows are not 4-byte aligned in RGB, but are in RGBA
    drawTopRedBottomBlue(target);
    const std::vector<std::uint8_t> rgba = target.readRgba();
    ASSERT_TRUE(noGlError());
    ASSERT_EQ(rgba.size(), 5u * 4u * 4u);
    EXPECT_EQ(pixelAt(rgba, 5, 0, 0), (Rgba{255, 0, 0, 255}));
    EXPECT_EQ(pixelAt(rgba, 5, 4, 1), (Rgba{255, 0, 0, 255}));
    EXPECT_EQ(pixelAt(rgba, 5, 0, 2), (Rgba{0, 0, 255, 255}));
    EXPECT_EQ(pixelAt(rgba, 5, 4, 3), (Rgba{0, 0, 255, 255}));
}

TEST_F(RenderTargetTest, ResizeReallocatesOnlyWhenTheSizeChanges) {
    RenderTarget target(Sampling::Nearest);
    ASSERT_TRUE(target.resize(8, 8).ok());
    const GLuint texture = target.colorTexture();
    ASSERT_TRUE(target.resize(8, 8).ok());
    ASSERT_TRUE(target.resize(3, 17).ok());
    EXPECT_EQ(target.colorTexture(), texture); // new storage, same texture: the UI's handle stays valid
    EXPECT_EQ(target.width(), 3);
    EXPECT_EQ(target.height(), 17);
    drawTopRedBottomBlue(target);
    EXPECT_EQ(target.readRgba().size(), 3u * 17u * 4u);
    target.setSampling(Sampling::Linear);
    GLint filter = 0;
    glBindTexture(GL_TEXTURE_2D, target.colorTexture());
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, &filter);
    EXPECT_EQ(filter, GL_LINEAR);
    EXPECT_TRUE(noGlError());
}

TEST_F(RenderTargetTest, SavePngWritesTheImageTopRowFirst) {
    RenderTarget target;
    ASSERT_TRUE(target.resize(6, 4).ok());
    drawTopRedBottomBlue(target);
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "dc_render_target_test.png";
    const Status saved = target.savePng(path.string());
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    ASSERT_TRUE(noGlError());

    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    std::filesystem::remove(path);
    ASSERT_FALSE(image.empty());
    EXPECT_EQ(image.cols, 6);
    EXPECT_EQ(image.rows, 4);
    ASSERT_EQ(image.type(), CV_8UC4);
    // OpenCV orders channels B, G, R, A.
    EXPECT_EQ(image.at<cv::Vec4b>(0, 0), cv::Vec4b(0, 0, 255, 255)); // red on top
    EXPECT_EQ(image.at<cv::Vec4b>(3, 5), cv::Vec4b(255, 0, 0, 255)); // blue below
}

} // namespace
} // namespace dc::render::test
