#include "frame/image_io.h"

#include "base/files.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

namespace dc::frame {

Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba) {
    if (width <= 0 || height <= 0 || rgba == nullptr)
        return Error{"cannot write " + path + ": empty image"};
    const cv::Mat view(height, width, CV_8UC4, const_cast<std::uint8_t*>(rgba));
    cv::Mat bgra;
    cv::cvtColor(view, bgra, cv::COLOR_RGBA2BGRA);
    std::vector<std::uint8_t> encoded;
    try {
        if (!cv::imencode(".png", bgra, encoded, {cv::IMWRITE_PNG_COMPRESSION, 3}))
            return Error{"cannot encode " + path + " as PNG"};
    } catch (const cv::Exception& e) {
        return Error{"cannot encode " + path + " as PNG: " + e.what()};
    }
    return base::writeFileAtomically(path, encoded);
}

} // namespace dc::frame
