#include "processing/infrared_image.h"

#include <algorithm>
#include <vector>

namespace dc::processing {

IntensityRange infraredContrastRange(const frame::Plane<std::uint16_t>& infrared) {
    if (infrared.empty())
        return {};
    // A histogram over every 16-bit value: one pass, no sort, whatever the image's size.
    std::vector<std::uint32_t> histogram(65536, 0);
    for (const std::uint16_t v : infrared.pixels)
        ++histogram[v];
    const std::size_t n = infrared.pixels.size();
    const std::size_t lowRank = n / 100;
    const std::size_t highRank = n - 1 - n / 100;
    IntensityRange range;
    std::size_t seen = 0;
    bool lowFound = false;
    for (std::size_t v = 0; v < histogram.size(); ++v) {
        seen += histogram[v];
        if (!lowFound && seen > lowRank) {
            range.low = static_cast<std::uint16_t>(v);
            lowFound = true;
        }
        if (seen > highRank) {
            range.high = static_cast<std::uint16_t>(v);
            break;
        }
    }
    return range;
}

RgbImage infraredRgbImage(const frame::Plane<std::uint16_t>& infrared, IntensityRange range) {
    RgbImage out{infrared.width, infrared.height, {}};
    out.pixels.resize(infrared.pixels.size() * 3);
    const float span = static_cast<float>(std::max(1, range.high - range.low));
    for (std::size_t i = 0; i < infrared.pixels.size(); ++i) {
        const float t = (static_cast<float>(infrared.pixels[i]) - range.low) / span;
        const auto gray = static_cast<std::uint8_t>(std::clamp(t, 0.0f, 1.0f) * 255.0f + 0.5f);
        std::fill_n(out.pixels.begin() + static_cast<std::ptrdiff_t>(3 * i), 3, gray);
    }
    return out;
}

} // namespace dc::processing
