#include "frame/color.h"
#include "frame/frame.h"

#include <gtest/gtest.h>

namespace dc::devices {
namespace {

// Full-range BT.601 codes of known colours, from the standard's definition (Y = 0.299 R + 0.587 G + 0.114 B,
// Cb = (B - Y) / 1.772, Cr = (R - Y) / 1.402), with chroma centred on 0.5 of full scale as in the sample.
struct Known {
    const char* name;
    frame::Rgb rgb;
    float y, cb, cr; // 8-bit codes
};

constexpr Known kKnown[] = {
    {"black", {0, 0, 0}, 0, 127.5f, 127.5f},       {"white", {1, 1, 1}, 255, 127.5f, 127.5f},
    {"red", {1, 0, 0}, 76.245f, 84.472f, 255.0f},  {"green", {0, 1, 0}, 149.685f, 43.028f, 20.735f},
    {"blue", {0, 0, 1}, 29.07f, 255.0f, 106.765f}, {"mid gray", {0.5f, 0.5f, 0.5f}, 127.5f, 127.5f, 127.5f},
};

TEST(Color, YcbcrToRgbReproducesKnownColors) {
    for (const Known& k : kKnown) {
        const frame::Rgb rgb = frame::ycbcrToRgb({k.y / 255.0f, k.cb / 255.0f, k.cr / 255.0f});
        EXPECT_NEAR(rgb.r, k.rgb.r, 2e-3) << k.name;
        EXPECT_NEAR(rgb.g, k.rgb.g, 2e-3) << k.name;
        EXPECT_NEAR(rgb.b, k.rgb.b, 2e-3) << k.name;
    }
}

TEST(Color, RgbToYcbcrMatchesTheStandard) {
    for (const Known& k : kKnown) {
        const frame::Ycbcr c = frame::rgbToYcbcr(k.rgb);
        EXPECT_NEAR(c.y * 255.0f, k.y, 0.05) << k.name;
        EXPECT_NEAR(c.cb * 255.0f, k.cb, 0.05) << k.name;
        EXPECT_NEAR(c.cr * 255.0f, k.cr, 0.05) << k.name;
    }
}

TEST(Color, ToByteClampsAndRejectsNan) {
    EXPECT_EQ(frame::toByte(-0.5f), 0);
    EXPECT_EQ(frame::toByte(2.0f), 255);
    EXPECT_EQ(frame::toByte(0.5f), 128);
    EXPECT_EQ(frame::toByte(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(Color, PixelRgbReadsEveryFormat) {
    // One 2x2 image per format, all pure red.
    const frame::Ycbcr red = frame::rgbToYcbcr({1, 0, 0});
    const std::uint8_t y = frame::toByte(red.y), cb = frame::toByte(red.cb), cr = frame::toByte(red.cr);
    frame::CapturedImage nv12{
        frame::PixelFormat::Nv12, 2, 2,
        std::make_shared<std::vector<std::uint8_t>>(std::vector<std::uint8_t>{y, y, y, y, cb, cr})};
    frame::CapturedImage yuyv{
        frame::PixelFormat::Yuyv, 2, 2,
        std::make_shared<std::vector<std::uint8_t>>(std::vector<std::uint8_t>{y, cb, y, cr, y, cb, y, cr})};
    frame::CapturedImage rgb{frame::PixelFormat::Rgb24, 2, 2,
                             std::make_shared<std::vector<std::uint8_t>>(std::vector<std::uint8_t>(12, 0))};
    for (int i = 0; i < 4; ++i)
        const_cast<std::vector<std::uint8_t>&>(*rgb.bytes)[i * 3] = 255;
    for (const frame::CapturedImage* image : {&nv12, &yuyv, &rgb}) {
        const frame::Rgb c = frame::pixelRgb(*image, 1, 1);
        EXPECT_NEAR(c.r, 1.0f, 0.02f) << toString(image->format);
        EXPECT_NEAR(c.g, 0.0f, 0.02f) << toString(image->format);
        EXPECT_NEAR(c.b, 0.0f, 0.02f) << toString(image->format);
    }
}

TEST(Color, PixelRgbOfAMalformedImageIsGrayNotACrash) {
    frame::CapturedImage truncated{frame::PixelFormat::Nv12, 64, 64,
                                   std::make_shared<std::vector<std::uint8_t>>(10)};
    const frame::Rgb c = frame::pixelRgb(truncated, 63, 63);
    EXPECT_FLOAT_EQ(c.r, 0.5f);
    EXPECT_FLOAT_EQ(frame::pixelRgb(frame::CapturedImage{}, 0, 0).g, 0.5f);
}

} // namespace
} // namespace dc::devices
