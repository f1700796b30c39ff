// The infrared panel's picture: a 1st-99th percentile stretch to gray, so a few glints or dead pixels do
// not flatten the image.

#include "processing/infrared_image.h"

#include <gtest/gtest.h>

namespace dc::processing {
namespace {

TEST(InfraredImage, TheContrastRangeIsThe1stTo99thPercentile) {
    // 1000 pixels: values 100..1099 in order, then the two lowest made 0 and the two highest 65535.
    frame::Plane<std::uint16_t> ir(100, 10);
    for (std::size_t i = 0; i < ir.pixels.size(); ++i)
        ir.pixels[i] = static_cast<std::uint16_t>(100 + i);
    ir.pixels[0] = ir.pixels[1] = 0;
    ir.pixels[998] = ir.pixels[999] = 65535;
    const IntensityRange range = infraredContrastRange(ir);
    // Rank 10 (of 0..999) is value 110 and rank 989 is 1089: the outliers decide nothing.
    EXPECT_EQ(range.low, 110);
    EXPECT_EQ(range.high, 1089);
    EXPECT_EQ(infraredContrastRange(frame::Plane<std::uint16_t>{}), IntensityRange{});
}

TEST(InfraredImage, TheRangeIsStretchedToBlackThroughWhiteInGray) {
    frame::Plane<std::uint16_t> ir(4, 1);
    ir.pixels = {5, 10, 15, 30};
    const RgbImage image = infraredRgbImage(ir, {10, 20});
    ASSERT_EQ(image.width, 4);
    ASSERT_EQ(image.height, 1);
    const std::vector<std::uint8_t> expected = {0, 0, 0, 0, 0, 0, 128, 128, 128, 255, 255, 255};
    EXPECT_EQ(image.pixels, expected);
    // One value everywhere: no division by zero; that value is the range's bottom, black.
    const RgbImage flat = infraredRgbImage(frame::Plane<std::uint16_t>(2, 2, 7), {7, 7});
    EXPECT_EQ(flat.pixels, std::vector<std::uint8_t>(12, 0));
}

} // namespace
} // namespace dc::processing
