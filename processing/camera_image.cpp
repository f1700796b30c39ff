#include "processing/camera_image.h"

#include "processing/resample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>

namespace dc::processing {

namespace {

bool wellFormed(const frame::CapturedImage& image) {
    return !image.empty() && image.raw() && image.width > 0 && image.height > 0 &&
           image.bytes->size() >= frame::CapturedImage::byteSize(image.format, image.width, image.height);
}

std::size_t yuyvRowBytes(int width) {
    return 4 * static_cast<std::size_t>((width + 1) / 2);
}

// YUYV's luma into a packed width x height plane.
void yuyvLuma(const frame::CapturedImage& image, std::uint8_t* out) {
    const std::uint8_t* bytes = image.bytes->data();
    for (int y = 0; y < image.height; ++y) {
        const std::uint8_t* in = bytes + y * yuyvRowBytes(image.width);
        for (int x = 0; x < image.width; ++x)
            out[static_cast<std::size_t>(y) * image.width + x] = in[(x / 2) * 4 + (x & 1) * 2];
    }
}

// YUYV's Y and CbCr as two planes (CbCr at half width).
void splitYuyv(const frame::CapturedImage& image, cv::Mat& luma, cv::Mat& chroma) {
    const int pairs = (image.width + 1) / 2;
    luma.create(image.height, image.width, CV_8U);
    yuyvLuma(image, luma.ptr<std::uint8_t>(0));
    chroma.create(image.height, pairs, CV_8UC2);
    for (int y = 0; y < image.height; ++y) {
        const std::uint8_t* in = image.bytes->data() + y * yuyvRowBytes(image.width);
        std::uint8_t* out = chroma.ptr<std::uint8_t>(y);
        for (int p = 0; p < pairs; ++p) {
            out[2 * p] = in[4 * p + 1];
            out[2 * p + 1] = in[4 * p + 3];
        }
    }
}

// `source` at `size` in `buffer` (resized to fit; its capacity kept), or `source` itself when it has the
// size already. Halving, the common case (a 1920x1440 camera image to 960x720), is OpenCV's vectorised 2x
// area path straight into the buffer; any other size goes through resized().
cv::Mat resizedInto(const cv::Mat& source, cv::Size size, std::vector<std::uint8_t>& buffer) {
    if (source.size() == size)
        return source;
    buffer.resize(static_cast<std::size_t>(size.area()) * source.elemSize());
    cv::Mat out(size, source.type(), buffer.data());
    if (size.width * 2 == source.cols && size.height * 2 == source.rows)
        cv::resize(source, out, size, 0, 0, cv::INTER_AREA);
    else
        resized(source, size).copyTo(out);
    return out;
}

ColorView viewOf(const cv::Mat& rgb) {
    return {rgb.ptr<std::uint8_t>(0), rgb.cols, rgb.rows, static_cast<std::ptrdiff_t>(rgb.step[0])};
}

// Y and interleaved CbCr planes, both at the output size, to packed RGB in scratch.rgb. OpenCV's YCrCb
// conversion is full-range BT.601 with coefficients (1.403, 0.714, 0.344, 1.773) that match the sample's
// (1.402, 0.7141, 0.3441, 1.772, frame::ycbcrToRgb) to 0.2 levels, and it is vectorised: ten times faster
// than a call per pixel.
ColorView ycbcrToRgbInto(const cv::Mat& luma, const cv::Mat& chroma, RgbScratch& scratch) {
    const auto bytes = static_cast<std::size_t>(luma.cols) * luma.rows * 3;
    scratch.ycrcb.resize(bytes);
    scratch.rgb.resize(bytes);
    cv::Mat ycrcb(luma.size(), CV_8UC3, scratch.ycrcb.data());
    const cv::Mat sources[] = {luma, chroma};
    const int fromTo[] = {0, 0, 1, 2, 2, 1}; // Y -> 0, Cb -> 2, Cr -> 1
    cv::mixChannels(sources, 2, &ycrcb, 1, fromTo, 3);
    cv::Mat rgb(luma.size(), CV_8UC3, scratch.rgb.data());
    cv::cvtColor(ycrcb, rgb, cv::COLOR_YCrCb2RGB);
    return viewOf(rgb);
}

} // namespace

GrayView lumaView(const frame::CapturedImage& image, std::vector<std::uint8_t>& scratch) {
    if (!wellFormed(image))
        return {};
    const std::uint8_t* bytes = image.bytes->data();
    const auto count = static_cast<std::size_t>(image.width) * image.height;
    switch (image.format) {
    case frame::PixelFormat::Nv12:
        return {bytes, image.width, image.height, image.width};
    case frame::PixelFormat::Yuyv:
        scratch.resize(count);
        yuyvLuma(image, scratch.data());
        return {scratch.data(), image.width, image.height, image.width};
    case frame::PixelFormat::Rgb24: {
        const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(bytes));
        scratch.resize(count);
        cv::Mat gray(image.height, image.width, CV_8U, scratch.data());
        cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY); // BT.601 weights, as rgbToYcbcr
        return {scratch.data(), image.width, image.height, image.width};
    }
    case frame::PixelFormat::Jpeg:
        break;
    }
    return {};
}

ColorView cameraRgbView(const frame::CapturedImage& image, int width, int height, RgbScratch& scratch) {
    if (!wellFormed(image) || width <= 0 || height <= 0)
        return {};
    const cv::Size size(width, height);
    auto* bytes = const_cast<std::uint8_t*>(image.bytes->data()); // cv::Mat wants non-const; only read
    switch (image.format) {
    case frame::PixelFormat::Nv12: {
        const cv::Mat luma(image.height, image.width, CV_8U, bytes);
        const cv::Mat chroma((image.height + 1) / 2, (image.width + 1) / 2, CV_8UC2,
                             bytes + static_cast<std::size_t>(image.width) * image.height);
        return ycbcrToRgbInto(resizedInto(luma, size, scratch.luma),
                              resizedInto(chroma, size, scratch.chroma), scratch);
    }
    case frame::PixelFormat::Yuyv: {
        cv::Mat luma, chroma;
        splitYuyv(image, luma, chroma);
        return ycbcrToRgbInto(resized(luma, size), resized(chroma, size), scratch);
    }
    case frame::PixelFormat::Rgb24:
        return viewOf(resizedInto(cv::Mat(image.height, image.width, CV_8UC3, bytes), size, scratch.rgb));
    case frame::PixelFormat::Jpeg:
        break;
    }
    return {};
}

std::array<int, 2> cameraPanelImageSize(const frame::CapturedImage& image, int shownWidth) {
    constexpr int kWidthStep = 64;
    const int stepped = (shownWidth + kWidthStep - 1) / kWidthStep * kWidthStep;
    const int width = std::clamp(stepped, 1, std::max(image.width, 1));
    return {width, std::max(1, image.height * width / std::max(image.width, 1))};
}

std::vector<std::uint8_t> cameraRgb(const frame::CapturedImage& image, int width, int height) {
    RgbScratch scratch;
    const ColorView view = cameraRgbView(image, width, height, scratch);
    if (view.empty())
        return {};
    const auto row = static_cast<std::size_t>(width) * 3;
    std::vector<std::uint8_t> rgb(row * height);
    for (int y = 0; y < height; ++y)
        std::copy_n(view.pixels + y * view.stride, row, rgb.data() + y * row);
    return rgb;
}

RgbImage cameraRgbImage(const frame::CapturedImage& image, int width, int height) {
    std::vector<std::uint8_t> rgb = cameraRgb(image, width, height);
    if (rgb.empty())
        return {};
    return {width, height, std::move(rgb)};
}

} // namespace dc::processing
