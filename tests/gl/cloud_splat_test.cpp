// The CPU splat path against the GL_POINTS path: the same cloud from the same view must cover the same
// pixels with the same colours, at every point size; anchors hide behind nearer points on both.

#include "gl_test_support.h"

#include "devices/synthetic/synthetic_device.h"
#include "processing/point_colours.h"
#include "render/cloud_splat.h"
#include "render/frame_textures.h"
#include "render/orbit_camera.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"

#include <utility>

namespace dc::render::test {
namespace {

constexpr int kSplatWidth = 480;
constexpr int kSplatHeight = 360;

class CloudSplatTest : public GlTest, public ::testing::WithParamInterface<float> {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_TRUE(renderer_.init().ok());
        ASSERT_TRUE(target_.resize(kSplatWidth, kSplatHeight).ok());
        frame_ = devices::SyntheticDevice{}.makeFrame(0, 0.0);
        uploadFrame(textures_, *frame_);
        const frame::Intrinsics k = frame_->depthIntrinsics();
        colours_ = processing::pointColours(frame_->capturedImage, k.width, k.height);
        // An oblique view, so that points overlap and the depth test decides.
        params_.viewProjection =
            cloudViewProjection({0.5f, 0.3f, 1.2f, {0.02f, -0.01f}}, 1.2f, verticalFovRadians(k),
                                float(kSplatWidth) / kSplatHeight);
        params_.pointSizePixels = GetParam();
        params_.background = kMagentaBackground;
    }

    std::vector<std::uint8_t> drawPoints() {
        renderer_.render(target_, textures_, params_);
        return target_.readRgba();
    }
    std::vector<std::uint8_t> drawSplat() {
        splatter_.splatSamples(*frame_->sceneDepth, frame_->depthIntrinsics(), &colours_, params_,
                               kSplatWidth, kSplatHeight);
        renderer_.renderSplat(target_, splatter_, params_);
        return target_.readRgba();
    }

    PointCloudRenderer renderer_;
    CloudSplatter splatter_;
    FrameTextures textures_;
    RenderTarget target_;
    frame::FramePtr frame_;
    processing::RgbImage colours_;
    CloudParams params_;
};

bool covered(const std::vector<std::uint8_t>& rgba, int x, int y) {
    return !(pixelAt(rgba, kSplatWidth, x, y) == Rgba{255, 0, 255, 255});
}

// Whether a pixel within one of (x, y) is covered: the masks may differ by a pixel at the silhouettes,
// where a point centre falls exactly on a pixel boundary.
bool coveredNear(const std::vector<std::uint8_t>& rgba, int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            if (x + dx >= 0 && x + dx < kSplatWidth && y + dy >= 0 && y + dy < kSplatHeight &&
                covered(rgba, x + dx, y + dy))
                return true;
    return false;
}

TEST_P(CloudSplatTest, SplatAndGlPointsAgree) {
    const std::vector<std::uint8_t> points = drawPoints();
    const std::vector<std::uint8_t> splat = drawSplat();
    ASSERT_TRUE(noGlError());
    int coveredBoth = 0, agreeing = 0, onlyOne = 0, coveredPoints = 0;
    for (int y = 0; y < kSplatHeight; ++y)
        for (int x = 0; x < kSplatWidth; ++x) {
            const bool p = covered(points, x, y);
            const bool s = covered(splat, x, y);
            coveredPoints += p;
            if ((p && !coveredNear(splat, x, y)) || (s && !coveredNear(points, x, y)))
                ++onlyOne;
            if (p && s) {
                ++coveredBoth;
                agreeing += static_cast<bool>(
                    near(pixelAt(points, kSplatWidth, x, y), pixelAt(splat, kSplatWidth, x, y), 6));
            }
        }
    ASSERT_GT(coveredPoints, kSplatWidth * kSplatHeight / 10) << "the scene fills the view";
    EXPECT_EQ(onlyOne, 0) << "coverage differs beyond a one-pixel border";
    EXPECT_GE(agreeing, coveredBoth * 99 / 100) << agreeing << " of " << coveredBoth << " pixels agree";
}

// Seen from the depth camera, samples land about two pixels apart here: points of the chosen size leave
// the background between them unless they grow to their footprint, which both paths do alike.
TEST_P(CloudSplatTest, FillingGapsLeavesNoBackgroundInsideASurfaceOnEitherPath) {
    frame_ = devices::SyntheticDevice{devices::SyntheticConfig{.noise = false}}.makeFrame(0, 0.0);
    uploadFrame(textures_, *frame_);
    const frame::Intrinsics k = frame_->depthIntrinsics();
    colours_ = processing::pointColours(frame_->capturedImage, k.width, k.height);
    params_.viewProjection =
        cloudViewProjection({}, 1.2f, verticalFovRadians(k), float(kSplatWidth) / kSplatHeight);
    const auto holes = [](const std::vector<std::uint8_t>& rgba) {
        int background = 0;
        for (int y = kSplatHeight / 4; y < 3 * kSplatHeight / 4; ++y)
            for (int x = kSplatWidth / 4; x < 3 * kSplatWidth / 4; ++x)
                background += !covered(rgba, x, y);
        return background;
    };
    if (GetParam() < 2.0f) {
        EXPECT_GT(holes(drawPoints()), kSplatWidth * kSplatHeight / 40)
            << "without filling, the samples stand apart";
        EXPECT_GT(holes(drawSplat()), kSplatWidth * kSplatHeight / 40);
    }
    params_.fillGaps = true;
    const std::vector<std::uint8_t> points = drawPoints();
    const std::vector<std::uint8_t> splat = drawSplat();
    ASSERT_TRUE(noGlError());
    EXPECT_EQ(holes(points), 0);
    EXPECT_EQ(holes(splat), 0);
    int differing = 0;
    for (int y = kSplatHeight / 4; y < 3 * kSplatHeight / 4; ++y)
        for (int x = kSplatWidth / 4; x < 3 * kSplatWidth / 4; ++x)
            differing += !near(pixelAt(points, kSplatWidth, x, y), pixelAt(splat, kSplatWidth, x, y), 6);
    EXPECT_LT(differing, kSplatWidth * kSplatHeight / 400) << "where a footprint rounds up on one path only";
}

// Without anchors the splat finishes the picture on the CPU; with one the keys go through a GL pass. An
// anchor far outside the view adds nothing to the image, so both ways must give the same pixels.
TEST_P(CloudSplatTest, TheFinishedPictureIsTheImageTheKeysPassDraws) {
    const std::vector<std::uint8_t> picture = drawSplat();
    ASSERT_FALSE(splatter_.picture().empty()) << "no anchors: the splat finishes the picture";
    const glm::vec4 outside = glm::inverse(params_.viewProjection) * glm::vec4(-4.0f, 0.0f, 0.5f, 1.0f);
    params_.anchors = {glm::vec3(outside) / outside.w};
    const std::vector<std::uint8_t> keys = drawSplat();
    ASSERT_TRUE(splatter_.picture().empty()) << "an anchor: the keys go to the GL pass";
    ASSERT_TRUE(noGlError());
    ASSERT_EQ(picture.size(), keys.size());
    int differing = 0, background = 0;
    for (int y = 0; y < kSplatHeight; ++y)
        for (int x = 0; x < kSplatWidth; ++x) {
            differing += !(pixelAt(picture, kSplatWidth, x, y) == pixelAt(keys, kSplatWidth, x, y));
            background += !covered(picture, x, y);
        }
    EXPECT_EQ(differing, 0);
    EXPECT_GT(background, 0) << "the background shows where no point landed";
    EXPECT_LT(background, kSplatWidth * kSplatHeight) << "points landed";
}

// The pixel (top row first, as readRgba returns them) a point of the depth camera's frame lands on.
std::pair<int, int> pixelOf(const glm::mat4& viewProjection, const glm::vec3& point) {
    const glm::vec4 clip = viewProjection * glm::vec4(point, 1.0f);
    const int x = static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * kSplatWidth);
    const int y = static_cast<int>((clip.y / clip.w * 0.5f + 0.5f) * kSplatHeight);
    return {x, kSplatHeight - 1 - y};
}

TEST_P(CloudSplatTest, AnchorsHideBehindNearerPointsOnBothPaths) {
    const std::vector<std::uint8_t> pointsAlone = drawPoints();
    const std::vector<std::uint8_t> splatAlone = drawSplat();
    // Two anchors on the view's ray through the scene's centre sample, one in front of it and one behind
    // it: only the first shows, on both paths.
    const frame::Intrinsics k = frame_->depthIntrinsics();
    const int u = k.width / 2;
    const int v = k.height / 2;
    const float z = frame_->sceneDepth->depthMeters.at(u, v);
    const glm::vec3 sample(float((u - k.cx) / k.fx) * z, float((v - k.cy) / k.fy) * z, z);
    const glm::vec4 clip = params_.viewProjection * glm::vec4(sample, 1.0f);
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    const auto onRay = [&](float ndcZ) {
        const glm::vec4 p = glm::inverse(params_.viewProjection) * glm::vec4(ndc.x, ndc.y, ndcZ, 1.0f);
        return glm::vec3(p) / p.w;
    };
    const glm::vec3 front = onRay(ndc.z - 0.3f * (ndc.z + 1.0f));
    const glm::vec3 behind = onRay(ndc.z + 0.5f * (1.0f - ndc.z));
    params_.anchorSizeMeters = 0.05f;
    const auto [x, y] = pixelOf(params_.viewProjection, sample);
    ASSERT_TRUE(x >= 0 && x < kSplatWidth && y >= 0 && y < kSplatHeight);
    ASSERT_TRUE(covered(pointsAlone, x, y));

    params_.anchors = {front};
    const std::vector<std::uint8_t> pointsFront = drawPoints();
    const std::vector<std::uint8_t> splatFront = drawSplat();
    EXPECT_NE(pixelAt(pointsFront, kSplatWidth, x, y), pixelAt(pointsAlone, kSplatWidth, x, y))
        << "the anchor shows";
    EXPECT_TRUE(near(pixelAt(splatFront, kSplatWidth, x, y), pixelAt(pointsFront, kSplatWidth, x, y), 2));

    params_.anchors = {behind};
    const std::vector<std::uint8_t> pointsBehind = drawPoints();
    const std::vector<std::uint8_t> splatBehind = drawSplat();
    ASSERT_TRUE(noGlError());
    EXPECT_EQ(pixelAt(pointsBehind, kSplatWidth, x, y), pixelAt(pointsAlone, kSplatWidth, x, y)) << "hidden";
    EXPECT_EQ(pixelAt(splatBehind, kSplatWidth, x, y), pixelAt(splatAlone, kSplatWidth, x, y)) << "hidden";
}

INSTANTIATE_TEST_SUITE_P(PointSizes, CloudSplatTest, ::testing::Values(1.0f, 2.0f, 5.0f));

} // namespace
} // namespace dc::render::test
