#include "gl_test_support.h"

#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"

namespace dc::render::test {
namespace {

// Odd and degenerate frames must draw something sensible (or nothing) without GL errors.
class RobustnessTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_TRUE(cloud_.init().ok());
        ASSERT_TRUE(panels_.init().ok());
    }

    // Uploads `frame` and draws every view into targets of the given size.
    ::testing::AssertionResult renderAll(const frame::Frame& frame, int width, int height) {
        uploadFrame(textures_, frame);
        if (!target_.resize(width, height).ok())
            return ::testing::AssertionFailure() << "cannot size the target";
        cloud_.render(target_, textures_, CloudParams{});
        panels_.renderDepth(target_, textures_, 0.5f, 3.0f);
        panels_.renderConfidence(target_, textures_);
        if (target_.readRgba().size() != static_cast<std::size_t>(width) * height * 4)
            return ::testing::AssertionFailure() << "wrong readback size";
        return noGlError();
    }

    PointCloudRenderer cloud_;
    PanelRenderer panels_;
    FrameTextures textures_;
    RenderTarget target_;
};

frame::DepthData depthOf(int width, int height, float meters) {
    return {frame::Plane<float>(width, height, meters), frame::Plane<std::uint8_t>(width, height, 1)};
}

const frame::Intrinsics kIntrinsics{4.0, 4.0, 2.0, 2.0, 4, 4};

TEST_F(RobustnessTest, OnePixelFrame) {
    const frame::Frame frame = makeFrame(depthOf(1, 1, 1.0f), nv12Image(1, 1, blockColors(1)), kIntrinsics);
    EXPECT_TRUE(renderAll(frame, 1, 1));
    EXPECT_EQ(textures_.depthWidth(), 1);
    EXPECT_EQ(cloud_.lastPointCount(), 1u);
}

TEST_F(RobustnessTest, OddSizedCameraImages) {
    const ColorFunction colours = blockColors(2);
    for (const auto& image : {nv12Image(5, 3, colours), yuyvImage(5, 3, colours), rgb24Image(5, 3, colours)})
        EXPECT_TRUE(renderAll(makeFrame(depthOf(3, 3, 1.0f), image, kIntrinsics), 7, 5));
}

TEST_F(RobustnessTest, FramesWithoutDepthConfidenceOrImage) {
    frame::Frame noDepth = makeFrame(depthOf(4, 4, 1.0f), nv12Image(4, 4, blockColors(2)), kIntrinsics);
    noDepth.sceneDepth.reset();
    EXPECT_TRUE(renderAll(noDepth, 4, 4));
    EXPECT_FALSE(textures_.hasDepth());

    frame::Frame noConfidence = makeFrame(depthOf(4, 4, 1.0f), {}, kIntrinsics);
    noConfidence.sceneDepth->confidence = {};
    EXPECT_TRUE(renderAll(noConfidence, 4, 4));
    EXPECT_FALSE(textures_.hasConfidence());

    EXPECT_TRUE(renderAll(frame::Frame{}, 2, 2));
}

TEST_F(RobustnessTest, MalformedInputsAreTreatedAsMissing) {
    frame::Frame frame = makeFrame(depthOf(4, 4, 1.0f), nv12Image(4, 4, blockColors(2)), kIntrinsics);
    frame.sceneDepth->confidence = frame::Plane<std::uint8_t>(3, 3, 2); // wrong size
    frame.capturedImage.width = 400;                                    // more pixels than bytes
    EXPECT_TRUE(renderAll(frame, 4, 4));
    EXPECT_TRUE(textures_.hasDepth());
    EXPECT_FALSE(textures_.hasConfidence());

    frame.cameraIntrinsics = {}; // depth without usable intrinsics cannot be unprojected
    uploadFrame(textures_, frame);
    cloud_.render(target_, textures_, CloudParams{});
    EXPECT_EQ(cloud_.lastPointCount(), 0u);
    EXPECT_TRUE(noGlError());
}

TEST_F(RobustnessTest, TexturesFollowChangingFrameSizes) {
    const ColorFunction colours = blockColors(4);
    EXPECT_TRUE(renderAll(makeFrame(depthOf(8, 6, 1.0f), nv12Image(16, 12, colours), kIntrinsics), 16, 12));
    EXPECT_TRUE(renderAll(makeFrame(depthOf(3, 2, 1.0f), nv12Image(6, 4, colours), kIntrinsics), 3, 2));
    EXPECT_TRUE(renderAll(makeFrame(depthOf(8, 6, 1.0f), nv12Image(16, 12, colours), kIntrinsics), 40, 30));
    EXPECT_EQ(textures_.depthWidth(), 8);
}

TEST_F(RobustnessTest, RenderingIntoAnUnsizedTargetOrBeforeInitDoesNothing) {
    uploadFrame(textures_, makeFrame(depthOf(4, 4, 1.0f), {}, kIntrinsics));
    RenderTarget unsized;
    cloud_.render(unsized, textures_, CloudParams{});
    panels_.renderDepth(unsized, textures_, 0.0f, 1.0f);
    PointCloudRenderer uninitialised;
    ASSERT_TRUE(target_.resize(4, 4).ok());
    uninitialised.render(target_, textures_, CloudParams{});
    EXPECT_EQ(uninitialised.lastPointCount(), 0u);
    EXPECT_TRUE(noGlError());
}

} // namespace
} // namespace dc::render::test
