#include "frame/image_io.h"

#include "frame/png_codec.h"

#include <opencv2/core.hpp>

namespace dc::frame {

Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba) {
    if (width <= 0 || height <= 0 || rgba == nullptr)
        return Error{"cannot write " + path + ": empty image"};
    const cv::Mat view(height, width, CV_8UC4, const_cast<std::uint8_t*>(rgba));
    return writePng(path, view, 3);
}

} // namespace dc::frame
