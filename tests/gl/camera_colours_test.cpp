// The GPU's camera colours against the CPU's: the cloud coloured by the shader (CameraColours) must show
// the colours processing::framePointColours makes, up to rounding, for one camera and for the two-sensor
// rig with its lens and its occlusions, decimated or not, from NV12, YUYV and RGB images; the CPU splat
// path with the CPU's colours must show the same picture.

#include "gl_test_support.h"

#include "devices/synthetic/synthetic_device.h"
#include "processing/decimation.h"
#include "processing/registration.h"
#include "processing/shown_frame.h"
#include "render/camera_colours.h"
#include "render/cloud_splat.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"

#include <cstdlib>

namespace dc::render::test {
namespace {

const glm::vec3 kBackground{1.0f, 0.0f, 1.0f}; // magenta: no colour of the synthetic scene
constexpr std::uint8_t kGray = processing::kUnseenGray;

struct Comparison {
    std::size_t covered = 0;    // pixels a point covers in the CPU-coloured picture
    std::size_t within1 = 0;    // of those, equal within one level per channel in the other picture
    std::size_t grayPoints = 0; // covered pixels the CPU left gray (unseen by the colour camera)
};

Comparison compare(const std::vector<std::uint8_t>& cpu, const std::vector<std::uint8_t>& other) {
    Comparison c;
    const Rgba background = toRgba(frame::Rgb{kBackground.r, kBackground.g, kBackground.b});
    for (std::size_t i = 0; i + 3 < cpu.size(); i += 4) {
        const Rgba a{cpu[i], cpu[i + 1], cpu[i + 2], cpu[i + 3]};
        if (a == background)
            continue;
        ++c.covered;
        c.grayPoints += a.r == kGray && a.g == kGray && a.b == kGray;
        const Rgba b{other[i], other[i + 1], other[i + 2], other[i + 3]};
        c.within1 += std::abs(a.r - b.r) <= 1 && std::abs(a.g - b.g) <= 1 && std::abs(a.b - b.b) <= 1;
    }
    return c;
}

class CameraColoursTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_TRUE(renderer_.init().ok());
        ASSERT_TRUE(camera_.init().ok());
    }

    // Draws the samples of `depth` seen straight from the depth camera (sample (u, v) on target pixel
    // (u, v)), coloured on the CPU and by the shader, and compares the two pictures.
    Comparison drawBoth(const frame::Frame& frame, const processing::ShownDepth& depth) {
        processing::CameraColourTable table;
        const auto colours =
            processing::framePointColours(frame, depth.data->depthMeters, depth.intrinsics, table).colors;
        EXPECT_TRUE(target_.resize(depth.width(), depth.height()).ok());
        textures_.uploadDepth(depth);
        textures_.uploadColors(colours.get());
        CloudParams params;
        params.viewProjection = pinholeViewProjection(depth.intrinsics, depth.width(), depth.height());
        params.pointSizePixels = 1.0f;
        params.background = kBackground;
        params.nearMeters = 0.0f;
        renderer_.render(target_, textures_, params);
        const std::vector<std::uint8_t> cpu = target_.readRgba();
        camera_.uploadImage(frame.capturedImage);
        camera_.setRig(frame.rig);
        camera_.renderNearest(textures_);
        renderer_.render(target_, textures_, params, &camera_);
        EXPECT_TRUE(noGlError());
        return compare(cpu, target_.readRgba());
    }

    static frame::FramePtr frameOf(const devices::SyntheticConfig& config) {
        devices::SyntheticDevice device(config);
        EXPECT_TRUE(device.open().ok()); // renders the camera image
        return device.makeFrame(0, 0.0);
    }
    static frame::FramePtr oneCameraFrame() { return frameOf({}); }
    static frame::FramePtr rigFrame() { return frameOf(devices::syntheticRigConfig()); }
    static processing::ShownDepth shownDepth(const frame::FramePtr& frame) {
        return {std::shared_ptr<const frame::DepthData>(frame, &*frame->sceneDepth),
                frame->depthIntrinsics()};
    }
    static processing::ShownDepth decimated(const processing::ShownDepth& depth, int factor) {
        processing::DecimatedDepth d =
            processing::decimateNearest(*depth.data, depth.intrinsics, factor, frame::Confidence::Low, 0.0f);
        return {d.data, d.intrinsics};
    }

    PointCloudRenderer renderer_;
    CameraColours camera_;
    FrameTextures textures_;
    RenderTarget target_;
};

::testing::AssertionResult sameUpToRounding(const Comparison& c, std::size_t minimumCovered) {
    if (c.covered < minimumCovered)
        return ::testing::AssertionFailure() << "only " << c.covered << " pixels covered";
    // A frame without its image would be gray on both paths. The rig's colour camera sees about half of
    // the depth camera's wider view (as a RealSense D4xx's does).
    if (c.grayPoints * 3 > c.covered * 2)
        return ::testing::AssertionFailure() << c.grayPoints << " of " << c.covered << " covered pixels gray";
    if (static_cast<double>(c.within1) < 0.999 * static_cast<double>(c.covered))
        return ::testing::AssertionFailure()
               << c.within1 << " of " << c.covered << " covered pixels within one level (< 99.9 %)";
    return ::testing::AssertionSuccess();
}

TEST_F(CameraColoursTest, OneCameraTheShaderColoursEqualTheCpuColours) {
    const frame::FramePtr frame = oneCameraFrame();
    ASSERT_FALSE(frame->rig);
    const processing::ShownDepth depth = shownDepth(frame);
    EXPECT_TRUE(sameUpToRounding(drawBoth(*frame, depth), 256 * 192 * 9 / 10));
    EXPECT_TRUE(sameUpToRounding(drawBoth(*frame, decimated(depth, 3)), 86 * 64 * 9 / 10));
    EXPECT_EQ(camera_.nearestPasses(), 0u) << "one camera hides nothing";
}

TEST_F(CameraColoursTest, EveryImageFormatGivesTheSameColours) {
    const frame::FramePtr nv12 = oneCameraFrame();
    const frame::CapturedImage& image = nv12->capturedImage;
    const ColorFunction colour = [&](int x, int y) { return frame::pixelRgb(image, x, y); };
    const processing::ShownDepth depth = shownDepth(nv12);
    for (const frame::CapturedImage& other :
         {yuyvImage(image.width, image.height, colour), rgb24Image(image.width, image.height, colour)}) {
        frame::Frame copy = *nv12;
        copy.capturedImage = other;
        EXPECT_TRUE(sameUpToRounding(drawBoth(copy, depth), 256 * 192 * 9 / 10))
            << frame::toString(other.format);
    }
}

TEST_F(CameraColoursTest, TheRigIsRegisteredThroughItsLensWithItsOcclusions) {
    const frame::FramePtr rig = rigFrame();
    ASSERT_TRUE(rig->rig);
    ASSERT_NE(rig->rig->colour.lens.model, frame::LensModel::None);
    // The rig's sensors 12 cm apart rather than 15 mm: near surfaces then hide wide bands of what lies
    // behind them from the colour camera (the registration is geometry; the image need not match it).
    auto wide = std::make_shared<frame::RigCalibration>(*rig->rig);
    wide->depthToColour.translationMeters[0] = -0.12;
    frame::Frame frame = *rig;
    frame.rig = wide;
    const processing::ShownDepth depth = shownDepth(rig);
    for (const int factor : {1, 2}) {
        const processing::ShownDepth drawn = factor == 1 ? depth : decimated(depth, factor);
        const std::size_t samples = static_cast<std::size_t>(drawn.width()) * drawn.height();
        EXPECT_TRUE(sameUpToRounding(drawBoth(*rig, drawn), samples * 8 / 10)) << "factor " << factor;
        EXPECT_TRUE(sameUpToRounding(drawBoth(frame, drawn), samples * 8 / 10)) << "wide, factor " << factor;
    }
    EXPECT_EQ(camera_.nearestPasses(), 4u);
}

TEST_F(CameraColoursTest, TheSplatPathShowsTheShadersColours) {
    const frame::FramePtr frame = rigFrame();
    const processing::ShownDepth depth = shownDepth(frame);
    processing::CameraColourTable table;
    const auto colours =
        processing::framePointColours(*frame, depth.data->depthMeters, depth.intrinsics, table).colors;
    ASSERT_TRUE(target_.resize(depth.width(), depth.height()).ok());
    CloudParams params;
    params.viewProjection = pinholeViewProjection(depth.intrinsics, depth.width(), depth.height());
    params.pointSizePixels = 1.0f;
    params.background = kBackground;
    params.nearMeters = 0.0f;
    CloudSplatter splatter;
    splatter.splatSamples(*depth.data, depth.intrinsics, colours.get(), params, depth.width(),
                          depth.height());
    renderer_.renderSplat(target_, splatter, params);
    const std::vector<std::uint8_t> splat = target_.readRgba();
    textures_.uploadDepth(depth);
    camera_.uploadImage(frame->capturedImage);
    camera_.setRig(frame->rig);
    camera_.renderNearest(textures_);
    renderer_.render(target_, textures_, params, &camera_);
    EXPECT_TRUE(sameUpToRounding(compare(splat, target_.readRgba()), 848 * 480 * 8 / 10));
}

} // namespace
} // namespace dc::render::test
