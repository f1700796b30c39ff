#include "gl_test_support.h"

#include "processing/point_colours.h"

#include <algorithm>
#include <cstdlib>
#include <memory>

namespace dc::render::test {

void GlTest::SetUp() {
    Expected<EglContext> context = EglContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    context_.emplace(std::move(context).value());
}

::testing::AssertionResult noGlError() {
    ::testing::AssertionResult result = ::testing::AssertionSuccess();
    for (GLenum error = glGetError(); error != GL_NO_ERROR; error = glGetError()) {
        if (result)
            result = ::testing::AssertionFailure() << "GL errors:";
        result << " 0x" << std::hex << error;
    }
    return result;
}

std::ostream& operator<<(std::ostream& out, const Rgba& c) {
    return out << '(' << int{c.r} << ", " << int{c.g} << ", " << int{c.b} << ", " << int{c.a} << ')';
}

Rgba pixelAt(const std::vector<std::uint8_t>& rgba, int width, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
}

Rgba toRgba(frame::Rgb c) {
    return {frame::toByte(c.r), frame::toByte(c.g), frame::toByte(c.b), 255};
}

Rgba toRgba(const std::array<float, 3>& c) {
    return toRgba(frame::Rgb{c[0], c[1], c[2]});
}

::testing::AssertionResult near(Rgba actual, Rgba expected, int tolerance) {
    const bool close = std::abs(actual.r - expected.r) <= tolerance &&
                       std::abs(actual.g - expected.g) <= tolerance &&
                       std::abs(actual.b - expected.b) <= tolerance && actual.a == expected.a;
    if (close)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << actual << " is not within " << tolerance << " of " << expected;
}

ColorFunction blockColors(int blockPixels) {
    return [blockPixels](int x, int y) {
        const int bx = x / blockPixels, by = y / blockPixels;
        // Small co-prime cycles give neighbouring blocks different colours in every channel.
        return frame::Rgb{0.1f + 0.8f * static_cast<float>((bx * 3 + by) % 5) / 4.0f,
                          0.1f + 0.8f * static_cast<float>((bx + 2 * by) % 4) / 3.0f,
                          0.1f + 0.8f * static_cast<float>((2 * bx + by) % 3) / 2.0f};
    };
}

namespace {

frame::CapturedImage makeImage(frame::PixelFormat format, int width, int height,
                               std::vector<std::uint8_t> bytes) {
    return {format, width, height, std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
}

frame::Ycbcr ycbcrAt(const ColorFunction& color, int x, int y) {
    return frame::rgbToYcbcr(color(x, y));
}

} // namespace

frame::CapturedImage nv12Image(int width, int height, const ColorFunction& color) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            bytes[static_cast<std::size_t>(y) * width + x] = frame::toByte(ycbcrAt(color, x, y).y);
    const int chromaWidth = (width + 1) / 2, chromaHeight = (height + 1) / 2;
    std::uint8_t* chroma = bytes.data() + static_cast<std::size_t>(width) * height;
    for (int y = 0; y < chromaHeight; ++y) {
        for (int x = 0; x < chromaWidth; ++x) {
            const frame::Ycbcr c = ycbcrAt(color, 2 * x, 2 * y);
            chroma[(y * chromaWidth + x) * 2] = frame::toByte(c.cb);
            chroma[(y * chromaWidth + x) * 2 + 1] = frame::toByte(c.cr);
        }
    }
    return makeImage(frame::PixelFormat::Nv12, width, height, std::move(bytes));
}

frame::CapturedImage yuyvImage(int width, int height, const ColorFunction& color) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(frame::PixelFormat::Yuyv, width, height));
    const int pairs = (width + 1) / 2;
    for (int y = 0; y < height; ++y) {
        for (int pair = 0; pair < pairs; ++pair) {
            std::uint8_t* p = bytes.data() + (static_cast<std::size_t>(y) * pairs + pair) * 4;
            const frame::Ycbcr left = ycbcrAt(color, 2 * pair, y);
            const frame::Ycbcr right = ycbcrAt(color, std::min(2 * pair + 1, width - 1), y);
            p[0] = frame::toByte(left.y);
            p[1] = frame::toByte(left.cb);
            p[2] = frame::toByte(right.y);
            p[3] = frame::toByte(left.cr);
        }
    }
    return makeImage(frame::PixelFormat::Yuyv, width, height, std::move(bytes));
}

frame::CapturedImage rgb24Image(int width, int height, const ColorFunction& color) {
    std::vector<std::uint8_t> bytes;
    bytes.reserve(frame::CapturedImage::byteSize(frame::PixelFormat::Rgb24, width, height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const frame::Rgb c = color(x, y);
            bytes.insert(bytes.end(), {frame::toByte(c.r), frame::toByte(c.g), frame::toByte(c.b)});
        }
    }
    return makeImage(frame::PixelFormat::Rgb24, width, height, std::move(bytes));
}

frame::Frame makeFrame(frame::DepthData depth, frame::CapturedImage image,
                       const frame::Intrinsics& cameraIntrinsics) {
    frame::Frame frame;
    frame.capturedImage = std::move(image);
    frame.cameraIntrinsics = cameraIntrinsics;
    frame.sceneDepth = std::move(depth);
    return frame;
}

glm::mat4 pinholeViewProjection(const frame::Intrinsics& k, int width, int height) {
    const auto w = static_cast<float>(width), h = static_cast<float>(height);
    const float nearMeters = 0.1f, farMeters = 100.0f;
    glm::mat4 m(0.0f); // glm is column-major: m[column][row]
    // Window x = u + 0.5 for u = fx x / z + cx; window y counts up from the bottom, so rows flip.
    m[0][0] = 2.0f * static_cast<float>(k.fx) / w;
    m[2][0] = 2.0f * (static_cast<float>(k.cx) + 0.5f) / w - 1.0f;
    m[1][1] = -2.0f * static_cast<float>(k.fy) / h;
    m[2][1] = 1.0f - 2.0f * (static_cast<float>(k.cy) + 0.5f) / h;
    m[2][2] = (farMeters + nearMeters) / (farMeters - nearMeters);
    m[3][2] = -2.0f * farMeters * nearMeters / (farMeters - nearMeters);
    m[2][3] = 1.0f; // clip w = z: the perspective divide
    return m;
}

void uploadFrame(FrameTextures& textures, const frame::Frame& frame) {
    processing::ShownDepth shown;
    if (frame.sceneDepth) {
        shown.data = std::make_shared<const frame::DepthData>(*frame.sceneDepth);
        shown.intrinsics = frame.depthIntrinsics();
    }
    textures.uploadDepth(shown);
    if (!shown.data) {
        textures.uploadColours(nullptr);
        return;
    }
    const processing::RgbImage colours =
        processing::pointColours(frame.capturedImage, shown.width(), shown.height());
    textures.uploadColours(&colours);
}

} // namespace dc::render::test
