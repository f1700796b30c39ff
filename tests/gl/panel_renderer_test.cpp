#include "gl_test_support.h"

#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/render_target.h"

#include <limits>

namespace dc::render::test {
namespace {

constexpr int kPanelWidth = 32;
constexpr int kPanelHeight = 8;
constexpr float kMinMeters = 1.0f;
constexpr float kMaxMeters = 4.0f;
const frame::Intrinsics kIntrinsics{30.0, 30.0, 16.0, 4.0, kPanelWidth, kPanelHeight};
const Rgba kBlack{0, 0, 0, 255};

class PanelRendererTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        const Status status = renderer_.init();
        ASSERT_TRUE(status.ok()) << status.error().message;
    }

    PanelRenderer renderer_;
    FrameTextures textures_;
    RenderTarget target_;
};

// Depth rising from 0.5 m to 4.5 m in reading order, so rows differ and an upside-down panel shows.
frame::DepthData rampDepth() {
    frame::DepthData depth{frame::Plane<float>(kPanelWidth, kPanelHeight),
                           frame::Plane<std::uint8_t>(kPanelWidth, kPanelHeight, 2)};
    for (int v = 0; v < kPanelHeight; ++v)
        for (int u = 0; u < kPanelWidth; ++u)
            depth.depthMeters.at(u, v) =
                0.5f + 4.0f * static_cast<float>(v * kPanelWidth + u) / (kPanelWidth * kPanelHeight);
    return depth;
}

Rgba expectedDepthColor(float d) {
    if (!(d > 0.0f) || std::isinf(d))
        return kBlack;
    return toRgba(jetColor((d - kMinMeters) / (kMaxMeters - kMinMeters)));
}

TEST_F(PanelRendererTest, DepthPanelIsTheJetColormapOfEachSample) {
    frame::DepthData depth = rampDepth();
    depth.depthMeters.at(3, 0) = 0.0f;
    depth.depthMeters.at(4, 2) = std::numeric_limits<float>::quiet_NaN();
    depth.depthMeters.at(5, 4) = -1.0f;
    depth.depthMeters.at(6, 7) = std::numeric_limits<float>::infinity();
    uploadFrame(textures_, makeFrame(depth, {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth, kPanelHeight).ok());
    renderer_.renderDepth(target_, textures_, kMinMeters, kMaxMeters);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    for (int v = 0; v < kPanelHeight; ++v) {
        for (int u = 0; u < kPanelWidth; ++u) {
            const Rgba expected = expectedDepthColor(depth.depthMeters.at(u, v));
            ASSERT_TRUE(near(pixelAt(rgba, kPanelWidth, u, v), expected, 1)) << "at " << u << ", " << v;
        }
    }
    EXPECT_EQ(pixelAt(rgba, kPanelWidth, 4, 2), kBlack); // NaN
}

// As an overlay the depth panel keeps its colours and lets the image beneath show where there is no depth.
TEST_F(PanelRendererTest, DepthOverlayHasTheSameColoursAndTransparentHoles) {
    frame::DepthData depth = rampDepth();
    depth.depthMeters.at(3, 0) = 0.0f;
    depth.depthMeters.at(4, 2) = std::numeric_limits<float>::quiet_NaN();
    depth.depthMeters.at(5, 4) = -1.0f;
    uploadFrame(textures_, makeFrame(depth, {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth, kPanelHeight).ok());
    renderer_.renderDepth(target_, textures_, kMinMeters, kMaxMeters, Colormap::Jet, DepthHoles::Transparent);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    for (int v = 0; v < kPanelHeight; ++v) {
        for (int u = 0; u < kPanelWidth; ++u) {
            const float d = depth.depthMeters.at(u, v);
            const Rgba expected = d > 0.0f ? expectedDepthColor(d) : Rgba{0, 0, 0, 0};
            ASSERT_TRUE(near(pixelAt(rgba, kPanelWidth, u, v), expected, 1)) << "at " << u << ", " << v;
        }
    }
}

class DepthColormapTest : public PanelRendererTest, public ::testing::WithParamInterface<Colormap> {};

TEST_P(DepthColormapTest, DepthPanelFollowsTheChosenColormap) {
    const frame::DepthData depth = rampDepth();
    uploadFrame(textures_, makeFrame(depth, {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth, kPanelHeight).ok());
    renderer_.renderDepth(target_, textures_, kMinMeters, kMaxMeters, GetParam());
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    for (int v = 0; v < kPanelHeight; ++v) {
        for (int u = 0; u < kPanelWidth; ++u) {
            const float t = (depth.depthMeters.at(u, v) - kMinMeters) / (kMaxMeters - kMinMeters);
            ASSERT_TRUE(near(pixelAt(rgba, kPanelWidth, u, v), toRgba(colormapColor(GetParam(), t)), 1))
                << "at " << u << ", " << v;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Colormaps, DepthColormapTest,
                         ::testing::Values(Colormap::Jet, Colormap::Turbo, Colormap::Viridis,
                                           Colormap::Grayscale),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(Colormap, JetStopsReproduceTheJetFunctionExactly) {
    for (int i = 0; i <= 1000; ++i) {
        const float t = static_cast<float>(i) / 1000.0f;
        const auto a = colormapColor(Colormap::Jet, t);
        const auto b = jetColor(t);
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(a[c], b[c], 1e-6f) << "t = " << t;
    }
}

TEST(Colormap, RampsRunTheirWholeRangeAndClampOutside) {
    EXPECT_EQ(colormapColor(Colormap::Grayscale, 0.25f)[1], 0.25f);
    EXPECT_EQ(colormapColor(Colormap::Viridis, -3.0f), colormapStops(Colormap::Viridis).front());
    EXPECT_EQ(colormapColor(Colormap::Turbo, 7.0f), colormapStops(Colormap::Turbo).back());
    EXPECT_EQ(colormapColor(Colormap::Turbo, std::numeric_limits<float>::quiet_NaN()),
              colormapStops(Colormap::Turbo).front());
    // Viridis gets brighter all the way, so it reads correctly in grayscale.
    float previous = -1.0f;
    for (const auto& c : colormapStops(Colormap::Viridis)) {
        const float luma = 0.299f * c[0] + 0.587f * c[1] + 0.114f * c[2];
        EXPECT_GT(luma, previous);
        previous = luma;
    }
}

TEST_F(PanelRendererTest, LargerDepthPanelRepeatsEachSampleWithoutBlending) {
    const frame::DepthData depth = rampDepth();
    uploadFrame(textures_, makeFrame(depth, {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth * 3, kPanelHeight * 3).ok());
    renderer_.renderDepth(target_, textures_, kMinMeters, kMaxMeters);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    for (int y = 0; y < target_.height(); ++y) {
        for (int x = 0; x < target_.width(); ++x) {
            const Rgba expected = expectedDepthColor(depth.depthMeters.at(x / 3, y / 3));
            ASSERT_TRUE(near(pixelAt(rgba, target_.width(), x, y), expected, 1)) << "at " << x << ", " << y;
        }
    }
}

TEST_F(PanelRendererTest, CollapsedDepthRangeDoesNotBreakTheShader) {
    uploadFrame(textures_, makeFrame(rampDepth(), {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth, kPanelHeight).ok());
    renderer_.renderDepth(target_, textures_, 2.0f, 2.0f);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    EXPECT_EQ(pixelAt(rgba, kPanelWidth, 0, 0), toRgba(jetColor(0.0f))); // 0.5 m, below the range
    EXPECT_EQ(pixelAt(rgba, kPanelWidth, kPanelWidth - 1, kPanelHeight - 1),
              toRgba(jetColor(1.0f))); // ~4.5 m, above it
}

TEST_F(PanelRendererTest, ConfidencePanelIsRedGreenBlue) {
    frame::DepthData depth = rampDepth();
    for (int v = 0; v < kPanelHeight; ++v)
        for (int u = 0; u < kPanelWidth; ++u)
            depth.confidence.at(u, v) = static_cast<std::uint8_t>((u + 2 * v) % 4); // 3 is out of range
    uploadFrame(textures_, makeFrame(depth, {}, kIntrinsics));
    ASSERT_TRUE(target_.resize(kPanelWidth, kPanelHeight).ok());
    renderer_.renderConfidence(target_, textures_);
    const std::vector<std::uint8_t> rgba = target_.readRgba();
    ASSERT_TRUE(noGlError());
    const Rgba colours[] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, kBlack};
    for (int v = 0; v < kPanelHeight; ++v)
        for (int u = 0; u < kPanelWidth; ++u)
            ASSERT_EQ(pixelAt(rgba, kPanelWidth, u, v), colours[depth.confidence.at(u, v)])
                << "at " << u << ", " << v;
}

TEST_F(PanelRendererTest, PanelsWithoutDepthAreBlack) {
    frame::Frame frame = makeFrame(rampDepth(), nv12Image(16, 16, blockColors(16)), kIntrinsics);
    frame.sceneDepth.reset();
    uploadFrame(textures_, frame);
    ASSERT_TRUE(target_.resize(16, 16).ok());
    renderer_.renderDepth(target_, textures_, kMinMeters, kMaxMeters);
    EXPECT_EQ(pixelAt(target_.readRgba(), 16, 8, 8), kBlack);
    renderer_.renderConfidence(target_, textures_);
    EXPECT_EQ(pixelAt(target_.readRgba(), 16, 8, 8), kBlack);
    EXPECT_TRUE(noGlError());
}

} // namespace
} // namespace dc::render::test
