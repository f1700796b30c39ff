#include "frame/jpeg_codec.h"

#include <turbojpeg.h>

#include <string>

namespace dc::frame {

namespace {

struct HandleDeleter {
    void operator()(void* handle) const { tjDestroy(handle); }
};
using Handle = std::unique_ptr<void, HandleDeleter>;

struct BufferDeleter {
    void operator()(unsigned char* buffer) const { tjFree(buffer); }
};

std::string errorOf(tjhandle handle) {
    return tjGetErrorStr2(handle);
}

// Planes of one image: Y at full size, Cb and Cr subsampled (4:2:0 or 4:2:2).
struct Planes {
    std::vector<std::uint8_t> y, cb, cr;
    int chromaWidth = 0;
    int chromaHeight = 0;
};

// TurboJPEG's SIMD code reads whole vectors, up to this many bytes past a plane's last pixel
// (AddressSanitizer caught it on a 7x5 image): each plane we hand it has this much more allocated behind it.
constexpr std::size_t kSimdSlack = 64;

void sizePlane(std::vector<std::uint8_t>& plane, std::size_t bytes) {
    plane.reserve(bytes + kSimdSlack);
    plane.resize(bytes);
}

// NV12's chroma is interleaved Cb, Cr at half size; its Y plane is used in place (the chroma behind it is
// its slack).
void splitNv12Chroma(const CapturedImage& image, Planes& planes) {
    planes.chromaWidth = (image.width + 1) / 2;
    planes.chromaHeight = (image.height + 1) / 2;
    const std::size_t n = static_cast<std::size_t>(planes.chromaWidth) * planes.chromaHeight;
    sizePlane(planes.cb, n);
    sizePlane(planes.cr, n);
    const std::uint8_t* chroma = image.bytes->data() + static_cast<std::size_t>(image.width) * image.height;
    for (std::size_t i = 0; i < n; ++i) {
        planes.cb[i] = chroma[2 * i];
        planes.cr[i] = chroma[2 * i + 1];
    }
}

// YUYV is Y0 Cb Y1 Cr per pixel pair, a row of 4 * ceil(w / 2) bytes.
void splitYuyv(const CapturedImage& image, Planes& planes) {
    const int w = image.width, h = image.height;
    planes.chromaWidth = (w + 1) / 2;
    planes.chromaHeight = h;
    sizePlane(planes.y, static_cast<std::size_t>(w) * h);
    sizePlane(planes.cb, static_cast<std::size_t>(planes.chromaWidth) * h);
    sizePlane(planes.cr, planes.cb.size());
    for (int row = 0; row < h; ++row) {
        const std::uint8_t* in = image.bytes->data() + static_cast<std::size_t>(row) * 4 * planes.chromaWidth;
        std::uint8_t* y = planes.y.data() + static_cast<std::size_t>(row) * w;
        const std::size_t c = static_cast<std::size_t>(row) * planes.chromaWidth;
        for (int pair = 0; pair < planes.chromaWidth; ++pair) {
            y[2 * pair] = in[4 * pair];
            if (2 * pair + 1 < w)
                y[2 * pair + 1] = in[4 * pair + 2];
            planes.cb[c + pair] = in[4 * pair + 1];
            planes.cr[c + pair] = in[4 * pair + 3];
        }
    }
}

void joinNv12Chroma(const Planes& planes, int width, int height, std::vector<std::uint8_t>& nv12) {
    std::uint8_t* chroma = nv12.data() + static_cast<std::size_t>(width) * height;
    for (std::size_t i = 0; i < planes.cb.size(); ++i) {
        chroma[2 * i] = planes.cb[i];
        chroma[2 * i + 1] = planes.cr[i];
    }
}

void joinYuyv(const Planes& planes, int width, int height, std::vector<std::uint8_t>& yuyv) {
    for (int row = 0; row < height; ++row) {
        std::uint8_t* out = yuyv.data() + static_cast<std::size_t>(row) * 4 * planes.chromaWidth;
        const std::uint8_t* y = planes.y.data() + static_cast<std::size_t>(row) * width;
        const std::size_t c = static_cast<std::size_t>(row) * planes.chromaWidth;
        for (int pair = 0; pair < planes.chromaWidth; ++pair) {
            out[4 * pair] = y[2 * pair];
            out[4 * pair + 1] = planes.cb[c + pair];
            out[4 * pair + 2] = 2 * pair + 1 < width ? y[2 * pair + 1] : y[2 * pair]; // odd width: padding
            out[4 * pair + 3] = planes.cr[c + pair];
        }
    }
}

} // namespace

struct JpegEncoder::Impl {
    Handle handle{tjInitCompress()};
    std::unique_ptr<unsigned char, BufferDeleter> buffer; // TurboJPEG's, grown as needed and kept
    unsigned long bufferSize = 0;
    Planes planes;

    Status compressPlanes(const std::uint8_t* y, int yStride, const CapturedImage& image, int subsamp,
                          int quality);
};

Status JpegEncoder::Impl::compressPlanes(const std::uint8_t* y, int yStride, const CapturedImage& image,
                                         int subsamp, int quality) {
    const unsigned char* src[3] = {y, planes.cb.data(), planes.cr.data()};
    const int strides[3] = {yStride, planes.chromaWidth, planes.chromaWidth};
    unsigned char* out = buffer.release();
    const int r = tjCompressFromYUVPlanes(handle.get(), src, image.width, strides, image.height, subsamp,
                                          &out, &bufferSize, quality, 0);
    buffer.reset(out);
    if (r != 0)
        return Error{"cannot encode the camera image as JPEG: " + errorOf(handle.get())};
    return {};
}

JpegEncoder::JpegEncoder() : impl_(std::make_unique<Impl>()) {}
JpegEncoder::~JpegEncoder() = default;
JpegEncoder::JpegEncoder(JpegEncoder&&) noexcept = default;
JpegEncoder& JpegEncoder::operator=(JpegEncoder&&) noexcept = default;

Expected<std::span<const std::uint8_t>> JpegEncoder::encode(const CapturedImage& image, int quality) {
    if (!impl_->handle)
        return Error{"cannot start the JPEG encoder"};
    Status s;
    switch (image.format) {
    case PixelFormat::Nv12:
        splitNv12Chroma(image, impl_->planes);
        s = impl_->compressPlanes(image.bytes->data(), image.width, image, TJSAMP_420, quality);
        break;
    case PixelFormat::Yuyv:
        splitYuyv(image, impl_->planes);
        s = impl_->compressPlanes(impl_->planes.y.data(), image.width, image, TJSAMP_422, quality);
        break;
    case PixelFormat::Rgb24: {
        unsigned char* out = impl_->buffer.release();
        const int r = tjCompress2(impl_->handle.get(), image.bytes->data(), image.width, 3 * image.width,
                                  image.height, TJPF_RGB, &out, &impl_->bufferSize, TJSAMP_420, quality, 0);
        impl_->buffer.reset(out);
        if (r != 0)
            s = Error{"cannot encode the camera image as JPEG: " + errorOf(impl_->handle.get())};
        break;
    }
    case PixelFormat::Jpeg:
        s = Error{"the camera image is a JPEG already"};
        break;
    }
    if (!s)
        return s.error();
    return std::span<const std::uint8_t>(impl_->buffer.get(), impl_->bufferSize);
}

// ---------------------------------------------------------------------------------------------------

struct JpegDecoder::Impl {
    Handle handle{tjInitDecompress()};
    Planes planes;

    // Decodes into Y (written straight to `y` with `yStride`), Cb and Cr planes.
    bool decodePlanes(std::span<const std::uint8_t> jpeg, std::uint8_t* y, int yStride, int width, int height,
                      int subsamp);
};

// Stop at the first warning (a truncated or corrupt stream), and refuse progressive streams with
// absurdly many scans, which take seconds to decode: a recording's JPEG is baseline and whole.
constexpr int kDecodeFlags = TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS;

bool JpegDecoder::Impl::decodePlanes(std::span<const std::uint8_t> jpeg, std::uint8_t* y, int yStride,
                                     int width, int height, int subsamp) {
    planes.chromaWidth = tjPlaneWidth(1, width, subsamp);
    planes.chromaHeight = tjPlaneHeight(1, height, subsamp);
    const std::size_t n = static_cast<std::size_t>(planes.chromaWidth) * planes.chromaHeight;
    sizePlane(planes.cb, n);
    sizePlane(planes.cr, n);
    unsigned char* dst[3] = {y, planes.cb.data(), planes.cr.data()};
    int strides[3] = {yStride, planes.chromaWidth, planes.chromaWidth};
    return tjDecompressToYUVPlanes(handle.get(), jpeg.data(), jpeg.size(), dst, width, strides, height,
                                   kDecodeFlags) == 0;
}

JpegDecoder::JpegDecoder() : impl_(std::make_unique<Impl>()) {}
JpegDecoder::~JpegDecoder() = default;
JpegDecoder::JpegDecoder(JpegDecoder&&) noexcept = default;
JpegDecoder& JpegDecoder::operator=(JpegDecoder&&) noexcept = default;

Expected<CapturedImage> JpegDecoder::decode(const CapturedImage& image) {
    if (image.raw())
        return image;
    if (image.empty())
        return Error{"empty JPEG camera image"};
    return decode(*image.bytes, image.width, image.height);
}

Expected<std::pair<int, int>> JpegDecoder::size(std::span<const std::uint8_t> jpeg) {
    int w = 0, h = 0, subsamp = -1, colorspace = -1;
    if (!impl_->handle || tjDecompressHeader3(impl_->handle.get(), jpeg.data(), jpeg.size(), &w, &h, &subsamp,
                                              &colorspace) != 0)
        return Error{"not a JPEG image"};
    return std::pair{w, h};
}

Expected<CapturedImage> JpegDecoder::decode(std::span<const std::uint8_t> jpeg, int width, int height) {
    tjhandle h = impl_->handle.get();
    int w = 0, ht = 0, subsamp = -1, colorspace = -1;
    if (!h || tjDecompressHeader3(h, jpeg.data(), jpeg.size(), &w, &ht, &subsamp, &colorspace) != 0)
        return Error{"not a JPEG image"};
    if (w != width || ht != height)
        return Error{"JPEG of " + std::to_string(w) + "x" + std::to_string(ht) + " in a " +
                     std::to_string(width) + "x" + std::to_string(height) + " section"};
    const bool ycbcr = colorspace == TJCS_YCbCr;
    const auto format = ycbcr && subsamp == TJSAMP_420   ? PixelFormat::Nv12
                        : ycbcr && subsamp == TJSAMP_422 ? PixelFormat::Yuyv
                                                         : PixelFormat::Rgb24;
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(CapturedImage::byteSize(format, w, ht));
    Planes& p = impl_->planes;
    bool ok = false;
    if (format == PixelFormat::Nv12) {
        ok = impl_->decodePlanes(jpeg, bytes->data(), w, w, ht, subsamp);
        if (ok)
            joinNv12Chroma(p, w, ht, *bytes);
    } else if (format == PixelFormat::Yuyv) {
        sizePlane(p.y, static_cast<std::size_t>(w) * ht);
        ok = impl_->decodePlanes(jpeg, p.y.data(), w, w, ht, subsamp);
        if (ok)
            joinYuyv(p, w, ht, *bytes);
    } else {
        ok = tjDecompress2(h, jpeg.data(), jpeg.size(), bytes->data(), w, 3 * w, ht, TJPF_RGB,
                           kDecodeFlags) == 0;
    }
    if (!ok)
        return Error{"cannot decode the JPEG camera image: " + errorOf(h)};
    return CapturedImage{format, w, ht, std::move(bytes)};
}

} // namespace dc::frame
