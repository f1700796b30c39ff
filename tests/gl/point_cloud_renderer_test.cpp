#include "gl_test_support.h"

#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"

#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cmath>
#include <limits>

namespace dc::render::test {
namespace {

// Depth is 64x48 and the camera image twice that, like a depth sensor beside a sharper color camera.
constexpr int kDepthWidth = 64;
constexpr int kDepthHeight = 48;
constexpr int kCameraScale = 2;
// Depth intrinsics fx = fy = 60, cx = 32, cy = 24 after scaling to the depth resolution.
const frame::Intrinsics kCameraIntrinsics{
    120.0, 120.0, 64.0, 48.0, kDepthWidth* kCameraScale, kDepthHeight* kCameraScale};
const glm::vec3 kRendererBackground{0.2f, 0.4f, 0.6f};

class PointCloudRendererTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        const Status status = renderer_.init();
        ASSERT_TRUE(status.ok()) << status.error().message;
        ASSERT_TRUE(target_.resize(kDepthWidth, kDepthHeight).ok());
        image_ = nv12Image(kCameraIntrinsics.width, kCameraIntrinsics.height, blockColors(16));
    }

    // Renders `depth` seen straight from the depth camera, so pixel (u, v) of the target shows depth
    // sample (u, v), and returns the target's pixels.
    std::vector<std::uint8_t> renderStraightOn(frame::DepthData depth, frame::Confidence minConfidence) {
        uploadFrame(textures_, makeFrame(std::move(depth), image_, kCameraIntrinsics));
        CloudParams params;
        params.viewProjection = pinholeViewProjection(textures_.depthIntrinsics(), kDepthWidth, kDepthHeight);
        params.minConfidence = minConfidence;
        params.pointSizePixels = 1.0f;
        params.background = kRendererBackground;
        renderer_.render(target_, textures_, params);
        return target_.readRgba();
    }

    Rgba background() const {
        return toRgba(frame::Rgb{kRendererBackground.r, kRendererBackground.g, kRendererBackground.b});
    }
    // The camera color at the centre of depth pixel (u, v); blocks are even-aligned, so any of the four
    // camera pixels under it has the same color.
    Rgba cameraColor(int u, int v) const {
        return toRgba(frame::pixelRgb(image_, u * kCameraScale, v * kCameraScale));
    }

    PointCloudRenderer renderer_;
    FrameTextures textures_;
    RenderTarget target_;
    frame::CapturedImage image_;
};

frame::DepthData plane(float depthMeters) {
    return {frame::Plane<float>(kDepthWidth, kDepthHeight, depthMeters),
            frame::Plane<std::uint8_t>(kDepthWidth, kDepthHeight, 2)};
}

TEST_F(PointCloudRendererTest, EveryPointLandsOnItsPixelWithTheCameraColor) {
    const std::vector<std::uint8_t> rgba = renderStraightOn(plane(1.0f), frame::Confidence::Low);
    ASSERT_TRUE(noGlError());
    EXPECT_EQ(renderer_.lastPointCount(), std::size_t{kDepthWidth * kDepthHeight});
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u)
            ASSERT_TRUE(near(pixelAt(rgba, kDepthWidth, u, v), cameraColor(u, v), 2))
                << "at " << u << ", " << v;
}

TEST_F(PointCloudRendererTest, InvalidAndNearSamplesLeaveTheBackground) {
    frame::DepthData depth = plane(1.0f);
    const float invalid[] = {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity(), 0.05f /* nearer than nearMeters */};
    // One column per kind of missing sample.
    for (int v = 0; v < kDepthHeight; ++v)
        for (int i = 0; i < 5; ++i)
            depth.depthMeters.at(10 + i, v) = invalid[i];
    const std::vector<std::uint8_t> rgba = renderStraightOn(std::move(depth), frame::Confidence::Low);
    ASSERT_TRUE(noGlError());
    for (int v = 0; v < kDepthHeight; ++v) {
        for (int u = 0; u < kDepthWidth; ++u) {
            const bool missing = u >= 10 && u < 15;
            const Rgba expected = missing ? background() : cameraColor(u, v);
            ASSERT_TRUE(near(pixelAt(rgba, kDepthWidth, u, v), expected, 2)) << "at " << u << ", " << v;
        }
    }
}

TEST_F(PointCloudRendererTest, PointsAreUnprojectedWithTheirDepth) {
    // Moving the eye 1/6 m to the left shifts a plane at depth z right by fx / 6 / z pixels: 10 px at 1 m,
    // 5 px at 2 m. A shader ignoring z (or the intrinsics) would shift both planes alike.
    for (const float z : {1.0f, 2.0f}) {
        uploadFrame(textures_, makeFrame(plane(z), image_, kCameraIntrinsics));
        CloudParams params;
        params.viewProjection =
            pinholeViewProjection(textures_.depthIntrinsics(), kDepthWidth, kDepthHeight) *
            glm::translate(glm::mat4(1.0f), glm::vec3(1.0f / 6.0f, 0.0f, 0.0f));
        params.pointSizePixels = 1.0f;
        params.background = kRendererBackground;
        renderer_.render(target_, textures_, params);
        const std::vector<std::uint8_t> rgba = target_.readRgba();
        ASSERT_TRUE(noGlError());
        const int shift = static_cast<int>(std::lround(10.0f / z));
        for (int u = 0; u < kDepthWidth; ++u) {
            const Rgba expected = u < shift ? background() : cameraColor(u - shift, 20);
            ASSERT_TRUE(near(pixelAt(rgba, kDepthWidth, u, 20), expected, 2)) << "z " << z << ", u " << u;
        }
    }
}

// Confidence cycles low, medium, high across the map; each level keeps exactly the samples at or above it.
TEST_F(PointCloudRendererTest, MinConfidenceRemovesExactlyTheLowerLevels) {
    frame::DepthData depth = plane(1.0f);
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u)
            depth.confidence.at(u, v) = static_cast<std::uint8_t>((u + v) % 3);
    for (const auto level : {frame::Confidence::Low, frame::Confidence::Medium, frame::Confidence::High}) {
        const std::vector<std::uint8_t> rgba = renderStraightOn(depth, level);
        ASSERT_TRUE(noGlError());
        std::array<int, 3> lit{};
        for (int v = 0; v < kDepthHeight; ++v)
            for (int u = 0; u < kDepthWidth; ++u)
                lit[static_cast<std::size_t>((u + v) % 3)] +=
                    pixelAt(rgba, kDepthWidth, u, v) != background();
        const int perClass = kDepthWidth * kDepthHeight / 3;
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(lit[static_cast<std::size_t>(c)], c >= static_cast<int>(level) ? perClass : 0)
                << "class " << c << " at min level " << static_cast<int>(level);
    }
}

TEST_F(PointCloudRendererTest, WithoutConfidenceEverySampleCountsAsHigh) {
    frame::DepthData depth = plane(1.0f);
    depth.confidence = {};
    const std::vector<std::uint8_t> rgba = renderStraightOn(std::move(depth), frame::Confidence::High);
    ASSERT_TRUE(noGlError());
    EXPECT_FALSE(textures_.hasConfidence());
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u)
            ASSERT_TRUE(near(pixelAt(rgba, kDepthWidth, u, v), cameraColor(u, v), 2))
                << "at " << u << ", " << v;
}

TEST_F(PointCloudRendererTest, WithoutCameraImageThePointsAreMidGray) {
    image_ = {};
    const std::vector<std::uint8_t> rgba = renderStraightOn(plane(1.0f), frame::Confidence::Low);
    ASSERT_TRUE(noGlError());
    EXPECT_TRUE(near(pixelAt(rgba, kDepthWidth, 5, 7), Rgba{128, 128, 128, 255}, 1));
}

TEST_F(PointCloudRendererTest, WithoutDepthOnlyTheBackgroundIsDrawn) {
    frame::Frame frame = makeFrame(plane(1.0f), image_, kCameraIntrinsics);
    frame.sceneDepth.reset();
    uploadFrame(textures_, frame);
    CloudParams params;
    params.background = kRendererBackground;
    renderer_.render(target_, textures_, params);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    EXPECT_FALSE(textures_.hasDepth());
    EXPECT_EQ(renderer_.lastPointCount(), 0u);
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u)
            ASSERT_EQ(pixelAt(rgba, kDepthWidth, u, v), background()) << "at " << u << ", " << v;
}

TEST_F(PointCloudRendererTest, LargerPointsCoverTheirNeighbourhood) {
    frame::DepthData depth = plane(0.0f);
    depth.depthMeters.at(30, 20) = 1.0f;
    uploadFrame(textures_, makeFrame(std::move(depth), image_, kCameraIntrinsics));
    CloudParams params;
    params.viewProjection = pinholeViewProjection(textures_.depthIntrinsics(), kDepthWidth, kDepthHeight);
    params.pointSizePixels = 3.0f;
    params.background = kRendererBackground;
    renderer_.render(target_, textures_, params);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    int lit = 0;
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u)
            lit += pixelAt(rgba, kDepthWidth, u, v) != background();
    EXPECT_EQ(lit, 9);
    EXPECT_TRUE(near(pixelAt(rgba, kDepthWidth, 29, 21), cameraColor(30, 20), 2));
}

// Each colouring of the points: the depth through the colormap over the given range, and the confidence
// in the confidence panel's colours.
TEST_F(PointCloudRendererTest, PointsTakeTheDepthColormapOrTheConfidenceColours) {
    frame::DepthData depth = plane(1.0f);
    for (int v = 0; v < kDepthHeight; ++v)
        for (int u = 0; u < kDepthWidth; ++u) {
            depth.depthMeters.at(u, v) = 1.0f + static_cast<float>(u) / kDepthWidth;
            depth.confidence.at(u, v) = static_cast<std::uint8_t>(v % 3);
        }
    uploadFrame(textures_, makeFrame(depth, image_, kCameraIntrinsics));
    CloudParams params;
    params.viewProjection = pinholeViewProjection(textures_.depthIntrinsics(), kDepthWidth, kDepthHeight);
    params.pointSizePixels = 1.0f;
    params.coloring = PointColoring::Depth;
    params.colormap = Colormap::Viridis;
    params.rangeMinMeters = 1.0f;
    params.rangeMaxMeters = 2.0f;
    renderer_.render(target_, textures_, params);
    std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    for (int u = 0; u < kDepthWidth; u += 7) {
        const float t = (depth.depthMeters.at(u, 10) - 1.0f) / 1.0f;
        ASSERT_TRUE(near(pixelAt(rgba, kDepthWidth, u, 10), toRgba(colormapColor(Colormap::Viridis, t)), 2))
            << "u " << u;
    }
    params.coloring = PointColoring::Confidence;
    renderer_.render(target_, textures_, params);
    rgba = target_.readRgba();
    const Rgba levels[] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}};
    for (int v = 0; v < kDepthHeight; v += 5)
        ASSERT_EQ(pixelAt(rgba, kDepthWidth, 12, v), levels[v % 3]) << "v " << v;
}

} // namespace
} // namespace dc::render::test
