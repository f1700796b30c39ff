// The GPU's camera colours against the CPU's: the cloud coloured by the shader (CameraColours) must show
// the colours processing::framePointColours makes, up to rounding, for one camera and for the two-sensor
// rig with its lens and its occlusions, decimated or not, from NV12, YUYV and RGB images; the CPU splat
// path with the CPU's colours must show the same picture.

#include "gl_test_support.h"

#include "devices/synthetic/synthetic_device.h"
#include "processing/camera_image.h"
#include "processing/decimation.h"
#include "processing/registration.h"
#include "processing/shown_frame.h"
#include "render/camera_colours.h"
#include "render/cloud_splat.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace dc::render::test {
namespace {

constexpr std::uint8_t kGray = processing::kUnseenGray;

struct Comparison {
    std::size_t covered = 0;    // pixels a point covers in the CPU-coloured picture
    std::size_t within1 = 0;    // of those, equal within one level per channel in the other picture
    std::size_t grayPoints = 0; // covered pixels the CPU left gray (unseen by the colour camera)
};

Comparison compare(const std::vector<std::uint8_t>& cpu, const std::vector<std::uint8_t>& other) {
    Comparison c;
    const Rgba background =
        toRgba(frame::Rgb{kMagentaBackground.r, kMagentaBackground.g, kMagentaBackground.b});
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
            processing::framePointColours(frame, depth.data->depthMeters, depth.intrinsics, table).colours;
        EXPECT_TRUE(target_.resize(depth.width(), depth.height()).ok());
        textures_.uploadDepth(depth);
        textures_.uploadColours(colours.get());
        CloudParams params;
        params.viewProjection = pinholeViewProjection(depth.intrinsics, depth.width(), depth.height());
        params.pointSizePixels = 1.0f;
        params.background = kMagentaBackground;
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
        processing::framePointColours(*frame, depth.data->depthMeters, depth.intrinsics, table).colours;
    ASSERT_TRUE(target_.resize(depth.width(), depth.height()).ok());
    CloudParams params;
    params.viewProjection = pinholeViewProjection(depth.intrinsics, depth.width(), depth.height());
    params.pointSizePixels = 1.0f;
    params.background = kMagentaBackground;
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

// Image pixels area-averaged into a width x height picture, each converted exactly by frame::pixelRgb (the
// sample's matrix), clamped and rounded as the GPU stores it: the reference of the camera panel.
std::vector<Rgba> areaAverage(const frame::CapturedImage& image, int width, int height) {
    std::vector<Rgba> out;
    const double sx = static_cast<double>(image.width) / width,
                 sy = static_cast<double>(image.height) / height;
    for (int oy = 0; oy < height; ++oy)
        for (int ox = 0; ox < width; ++ox) {
            double r = 0, g = 0, b = 0, total = 0;
            for (int y = static_cast<int>(oy * sy); y < std::ceil((oy + 1) * sy); ++y)
                for (int x = static_cast<int>(ox * sx); x < std::ceil((ox + 1) * sx); ++x) {
                    const double w = (std::min((ox + 1) * sx, x + 1.0) - std::max(ox * sx, double(x))) *
                                     (std::min((oy + 1) * sy, y + 1.0) - std::max(oy * sy, double(y)));
                    const frame::Rgb c = frame::pixelRgb(image, x, y);
                    r += w * c.r, g += w * c.g, b += w * c.b, total += w;
                }
            out.push_back(toRgba(frame::Rgb{float(r / total), float(g / total), float(b / total)}));
        }
    return out;
}

// How many pixels of a picture (RGBA, top row first) are within `levels` of the reference on every channel.
std::size_t within(const std::vector<std::uint8_t>& rgba, const std::vector<std::uint8_t>& rgb, int levels) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < rgb.size() / 3; ++i) {
        bool close = true;
        for (std::size_t c = 0; c < 3; ++c)
            close &= std::abs(rgba[i * 4 + c] - rgb[i * 3 + c]) <= levels;
        n += close;
    }
    return n;
}

// The camera panel's picture from the shader: each pixel the area average of the image pixels it covers,
// converted with the sample's matrix, at half the image's size and at a panel's stepped size, from each
// image format. At half size the CPU's panel (OpenCV's area resize rounded to bytes, and its YCrCb matrix
// 0.2 levels off the sample's) is within two levels of it; at other scales OpenCV halves first and resizes
// the rest, which is no longer the area average at edges (up to 8 levels at 0.2 % of a 384-wide panel).
TEST_F(CameraColoursTest, TheCameraPanelFromTheShaderIsTheAreaAverageOfTheImage) {
    const frame::FramePtr nv12 = rigFrame(); // a 1280x720 colour image through a lens
    const frame::CapturedImage& image = nv12->capturedImage;
    const ColorFunction colour = [&](int x, int y) { return frame::pixelRgb(image, x, y); };
    RenderTarget target(Sampling::Nearest, DepthBuffer::Without);
    for (const frame::CapturedImage& shown : {image, yuyvImage(image.width, image.height, colour),
                                              rgb24Image(image.width, image.height, colour)}) {
        camera_.uploadImage(shown);
        for (const auto& [w, h] : {std::pair{640, 360}, std::pair{384, 216}}) {
            camera_.renderImage(target, w, h);
            const std::vector<std::uint8_t> gpu = target.readRgba();
            std::vector<std::uint8_t> reference;
            for (const Rgba& c : areaAverage(shown, w, h))
                reference.insert(reference.end(), {c.r, c.g, c.b});
            const auto n = static_cast<double>(w * h);
            const std::string where = std::string(frame::toString(shown.format)) + " at " + std::to_string(w);
            EXPECT_GE(static_cast<double>(within(gpu, reference, 1)), 0.999 * n) << where;
            const processing::RgbImage cpu = processing::cameraRgbImage(shown, w, h);
            if (w * 2 == shown.width) { // OpenCV's halving is an exact box; other scales go in two steps
                EXPECT_GE(static_cast<double>(within(gpu, cpu.pixels, 2)), 0.999 * n)
                    << where << ", the CPU's";
            }
        }
    }
    EXPECT_EQ(camera_.imagePasses(), 6u);
    EXPECT_TRUE(noGlError());
}

} // namespace
} // namespace dc::render::test
