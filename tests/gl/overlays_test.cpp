// The overlays the GL path makes from the camera's planes against the CPU's: the depth panel's colour
// overlay (CameraColours::renderSeenColours) must be processing::seenColourOverlay at the cells the panel
// shows, colours and seen/unseen alike, and the depth over the camera (CameraColours::renderAlignedDepth)
// processing::alignDepthToColour in the depth panel's colormap, holes transparent; for one camera and for
// the two-sensor rig with its lens and its occlusions.

#include "gl_test_support.h"

#include "devices/synthetic/synthetic_device.h"
#include "processing/camera_image.h"
#include "processing/registration.h"
#include "processing/shown_frame.h"
#include "render/camera_colours.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/render_target.h"
#include "tests/small_rig.h"

#include <algorithm>
#include <cstdlib>
#include <string>

namespace dc::render::test {
namespace {

// Pixel by pixel: alpha (seen or not) must agree, and where both are opaque the colour within a level.
struct OverlayComparison {
    std::size_t pixels = 0;
    std::size_t alphaAgree = 0;
    std::size_t opaque = 0;      // opaque in the CPU's picture
    std::size_t transparent = 0; // transparent in the CPU's picture
    std::size_t colourWithin1 = 0;
};

void addPixel(OverlayComparison& c, Rgba cpu, Rgba gpu) {
    ++c.pixels;
    const bool cpuSeen = cpu.a != 0, gpuSeen = gpu.a != 0;
    c.alphaAgree += cpuSeen == gpuSeen;
    c.opaque += cpuSeen;
    c.transparent += !cpuSeen;
    c.colourWithin1 += !cpuSeen || (gpuSeen && std::abs(cpu.r - gpu.r) <= 1 && std::abs(cpu.g - gpu.g) <= 1 &&
                                    std::abs(cpu.b - gpu.b) <= 1 && gpu.a == 255 && cpu.a == 255);
}

// Each within one level in 8 bits on 99.9 % of pixels, with at least `minimumOpaque` of them seen (and
// `minimumTransparent` unseen): an overlay that lost its colours, or saw everything, fails.
::testing::AssertionResult sameOverlay(const OverlayComparison& c, double minimumOpaque,
                                       double minimumTransparent) {
    const auto n = static_cast<double>(c.pixels);
    if (c.pixels == 0)
        return ::testing::AssertionFailure() << "nothing compared";
    if (static_cast<double>(c.opaque) < minimumOpaque * n ||
        static_cast<double>(c.transparent) < minimumTransparent * n)
        return ::testing::AssertionFailure()
               << c.opaque << " opaque, " << c.transparent << " transparent of " << c.pixels;
    if (static_cast<double>(c.alphaAgree) < 0.999 * n)
        return ::testing::AssertionFailure()
               << "seen/unseen agree on " << c.alphaAgree << " of " << c.pixels << " (< 99.9 %)";
    if (static_cast<double>(c.colourWithin1) < 0.999 * n)
        return ::testing::AssertionFailure()
               << c.colourWithin1 << " of " << c.pixels << " pixels within one level (< 99.9 %)";
    return ::testing::AssertionSuccess();
}

class OverlaysTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_TRUE(camera_.init().ok());
    }

    static frame::FramePtr frameOf(const devices::SyntheticConfig& config) {
        devices::SyntheticDevice device(config);
        EXPECT_TRUE(device.open().ok()); // renders the camera image
        return device.makeFrame(0, 0.0);
    }
    static processing::ShownDepth shownDepth(const frame::FramePtr& frame) {
        return {std::shared_ptr<const frame::DepthData>(frame, &*frame->sceneDepth),
                frame->depthIntrinsics()};
    }

    // The GPU's colour overlay of `frame` at every `step`-th cell against the CPU's overlay of every sample
    // read at the same cells (processing::sampleCellCentres' choice).
    OverlayComparison compareColours(const frame::FramePtr& frame, int step) {
        const processing::ShownDepth depth = shownDepth(frame);
        processing::CameraColourTable table;
        const processing::RgbaImage cpu = processing::seenColourOverlay(
            processing::framePointColours(*frame, depth.data->depthMeters, table));
        textures_.uploadDepth(depth);
        camera_.uploadImage(frame->capturedImage);
        camera_.setRig(frame->rig);
        camera_.renderSeenColours(target_, textures_, step);
        EXPECT_TRUE(noGlError());
        const int w = target_.width(), h = target_.height();
        EXPECT_EQ(w, (depth.width() + step - 1) / step);
        EXPECT_EQ(h, (depth.height() + step - 1) / step);
        const std::vector<std::uint8_t> gpu = target_.readRgba();
        OverlayComparison c;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int u = std::min(cpu.width - 1, x * step + step / 2);
                const int v = std::min(cpu.height - 1, y * step + step / 2);
                const std::size_t i = (static_cast<std::size_t>(v) * cpu.width + u) * 4;
                const Rgba expected{cpu.pixels[i], cpu.pixels[i + 1], cpu.pixels[i + 2], cpu.pixels[i + 3]};
                addPixel(c, expected, pixelAt(gpu, w, x, y));
            }
        return c;
    }

    // The GPU's depth over the camera at width x height against the CPU's aligned depth, colormapped.
    OverlayComparison compareAligned(const frame::FramePtr& frame, int width, int height) {
        const processing::ShownDepth depth = shownDepth(frame);
        const CameraColours::AlignedColours colours{0.3f, 2.2f, Colormap::Turbo};
        const frame::Plane<float> aligned =
            processing::alignDepthToColour(depth.data->depthMeters, *frame->rig, width, height);
        textures_.uploadDepth(depth);
        camera_.setRig(frame->rig);
        camera_.renderAlignedDepth(alignedTarget_, textures_, width, height, colours);
        EXPECT_TRUE(noGlError());
        EXPECT_EQ(alignedTarget_.width(), width);
        EXPECT_EQ(alignedTarget_.height(), height);
        const std::vector<std::uint8_t> gpu = alignedTarget_.readRgba();
        OverlayComparison c;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float d = aligned.at(x, y);
                const Rgba expected =
                    d > 0.0f
                        ? toRgba(colormapColor(colours.colormap, (d - colours.minMeters) /
                                                                     (colours.maxMeters - colours.minMeters)))
                        : Rgba{};
                addPixel(c, expected, pixelAt(gpu, width, x, y));
            }
        return c;
    }

    static frame::FramePtr wideRigFrame() {
        // The rig's sensors 12 cm apart rather than 15 mm: near surfaces then hide wide bands of what lies
        // behind them from the colour camera.
        const frame::FramePtr rig = frameOf(dc::test::smallRigConfig());
        auto wide = std::make_shared<frame::RigCalibration>(*rig->rig);
        wide->depthToColour.translationMeters[0] = -0.12;
        auto copy = std::make_shared<frame::Frame>(*rig);
        copy->rig = wide;
        return copy;
    }

    CameraColours camera_;
    FrameTextures textures_;
    RenderTarget target_{Sampling::Nearest, DepthBuffer::Without};
    RenderTarget alignedTarget_{Sampling::Nearest, DepthBuffer::With};
};

TEST_F(OverlaysTest, OneCameraTheColourOverlayIsTheCpusAtTheShownCells) {
    const frame::FramePtr frame = frameOf({});
    ASSERT_FALSE(frame->rig);
    for (const int step : {1, 3}) // one camera sees every sample: all opaque
        EXPECT_TRUE(sameOverlay(compareColours(frame, step), 1.0, 0.0)) << "step " << step;
    EXPECT_EQ(camera_.nearestPasses(), 0u) << "one camera hides nothing";
    EXPECT_EQ(camera_.seenPasses(), 2u);
}

TEST_F(OverlaysTest, TheRigsColourOverlayIsTheCpusThroughItsLensWithItsOcclusions) {
    const frame::FramePtr rig = frameOf(dc::test::smallRigConfig());
    ASSERT_TRUE(rig->rig);
    ASSERT_NE(rig->rig->colour.lens.model, frame::LensModel::None);
    ASSERT_TRUE(processing::shaderCanColour(rig->rig.get()));
    const frame::FramePtr wide = wideRigFrame();
    for (const int step : {1, 2}) {
        // The colour camera sees about half of the depth camera's wider view.
        EXPECT_TRUE(sameOverlay(compareColours(rig, step), 0.3, 0.1)) << "step " << step;
        EXPECT_TRUE(sameOverlay(compareColours(wide, step), 0.3, 0.1)) << "wide, step " << step;
    }
    EXPECT_EQ(camera_.nearestPasses(), 4u) << "every overlay tests visibility";
}

TEST_F(OverlaysTest, TheDepthOverTheCameraIsTheCpusAlignedDepthColormapped) {
    const frame::FramePtr rig = frameOf(dc::test::smallRigConfig());
    const frame::FramePtr wide = wideRigFrame();
    const frame::CapturedImage& image = rig->capturedImage;
    for (const int shownWidth : {320, 128}) {
        const auto [w, h] = processing::cameraPanelImageSize(image, shownWidth);
        EXPECT_TRUE(sameOverlay(compareAligned(rig, w, h), 0.5, 0.0)) << "at " << w;
        EXPECT_TRUE(sameOverlay(compareAligned(wide, w, h), 0.5, 0.0)) << "wide, at " << w;
    }
    EXPECT_EQ(camera_.alignedPasses(), 4u);
}

} // namespace
} // namespace dc::render::test
