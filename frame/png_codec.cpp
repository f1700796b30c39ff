#include "frame/png_codec.h"

#include "base/files.h"

#include <png.h>

#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>

namespace dc::frame {

namespace {

// A corrupt or hostile header must not make us allocate gigabytes; the largest image a capture holds is far
// smaller (a 4K 16-bit RGBA frame is 64 MiB).
constexpr std::size_t kMaxDecodedBytes = std::size_t{1} << 30;

// libpng reports an error by calling onError, which must not return: it keeps the message here and
// longjmps back to the setjmp of the one small function that called libpng (prepareRead, readPixels,
// writeImage). Those functions hold no object with a destructor across the jump: whatever they fill is
// owned by their callers' frames, which a longjmp does not skip.
struct Io {
    const std::uint8_t* data = nullptr; // reading: the whole file
    std::size_t size = 0;
    std::size_t offset = 0;
    std::vector<std::uint8_t>* out = nullptr; // writing
    char message[192] = "";
};

[[noreturn]] void onError(png_structp png, png_const_charp message) {
    auto* io = static_cast<Io*>(png_get_error_ptr(png));
    std::snprintf(io->message, sizeof(io->message), "%s", message);
    png_longjmp(png, 1);
}

// Warnings are about ancillary chunks (a colour profile, a text field) and never about pixels; a library
// printing them on stderr would only confuse the tool's own output.
void onWarning(png_structp, png_const_charp) {}

void readBytes(png_structp png, png_bytep out, std::size_t length) {
    auto* io = static_cast<Io*>(png_get_io_ptr(png));
    if (length > io->size - io->offset)
        png_error(png, "the file ends early (truncated)");
    std::memcpy(out, io->data + io->offset, length);
    io->offset += length;
}

void appendBytes(png_structp png, png_bytep data, std::size_t length) {
    auto* io = static_cast<Io*>(png_get_io_ptr(png));
    bool grown = true;
    try {
        io->out->insert(io->out->end(), data, data + length);
    } catch (const std::bad_alloc&) {
        grown = false;
    }
    if (!grown) // outside the handler: a longjmp must not leave an exception half handled
        png_error(png, "out of memory");
}

void flushNothing(png_structp) {} // libpng's default flush would fflush() our Io as a FILE*

// The image as libpng will deliver it once its transformations are set.
struct Layout {
    png_uint_32 width = 0;
    png_uint_32 height = 0;
    int bitDepth = 0;
    int channels = 0;
    std::size_t rowBytes = 0;
};

bool prepareRead(png_structp png, png_infop info, PngPixels pixels, Layout& layout) {
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_set_read_fn(png, png_get_error_ptr(png), readBytes);
    png_read_info(png, info);
    png_set_expand(png); // a palette to RGB(A), gray below 8 bits to 8, transparency to alpha
    if (pixels == PngPixels::Rgb8) {
        png_set_scale_16(png);
        png_set_strip_alpha(png);
        png_set_gray_to_rgb(png);
    } else if (png_get_bit_depth(png, info) == 16 && std::endian::native == std::endian::little) {
        png_set_swap(png);
    }
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    layout = {png_get_image_width(png, info), png_get_image_height(png, info), png_get_bit_depth(png, info),
              png_get_channels(png, info), png_get_rowbytes(png, info)};
    return true;
}

bool readPixels(png_structp png, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_read_image(png, rows);
    png_read_end(png, nullptr);
    return true;
}

void destroyRead(png_structpp png, png_infopp info) {
    png_destroy_read_struct(png, info, nullptr);
}

// libpng's structs of one read or write, made with errors reported through `io`; `info` is null where
// they could not be made. Destroyed together however far their setup went.
template <auto Create, auto Destroy> struct PngStructs {
    png_structp png = nullptr;
    png_infop info = nullptr;
    explicit PngStructs(Io& io) : png(Create(PNG_LIBPNG_VER_STRING, &io, onError, onWarning)) {
        if (png)
            info = png_create_info_struct(png);
    }
    PngStructs(const PngStructs&) = delete;
    PngStructs& operator=(const PngStructs&) = delete;
    ~PngStructs() { Destroy(&png, &info); }
};
using ReadStructs = PngStructs<png_create_read_struct, destroyRead>;
using WriteStructs = PngStructs<png_create_write_struct, png_destroy_write_struct>;

bool writeImage(png_structp png, png_infop info, const Layout& layout, int colorType, int compressionLevel,
                png_bytepp rows) {
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_set_write_fn(png, png_get_error_ptr(png), appendBytes, flushNothing);
    png_set_IHDR(png, info, layout.width, layout.height, layout.bitDepth, colorType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, compressionLevel);
    png_write_info(png, info);
    if (layout.bitDepth == 16 && std::endian::native == std::endian::little)
        png_set_swap(png);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    return true;
}

int colorTypeOf(int channels) {
    switch (channels) {
    case 1:
        return PNG_COLOR_TYPE_GRAY;
    case 3:
        return PNG_COLOR_TYPE_RGB;
    default:
        return PNG_COLOR_TYPE_RGB_ALPHA;
    }
}

} // namespace

bool looksLikePng(std::span<const std::uint8_t> bytes) {
    return bytes.size() >= 8 && png_sig_cmp(bytes.data(), 0, 8) == 0;
}

Expected<cv::Mat> decodePng(std::span<const std::uint8_t> png, PngPixels pixels) {
    if (!looksLikePng(png))
        return Error{"not a PNG image"};
    Io io{.data = png.data(), .size = png.size()};
    ReadStructs s(io);
    if (!s.info)
        return Error{"cannot start the PNG decoder"};
    Layout layout;
    if (!prepareRead(s.png, s.info, pixels, layout))
        return Error{std::string("not a valid PNG image: ") + io.message};
    if (layout.rowBytes * layout.height > kMaxDecodedBytes)
        return Error{"PNG image of " + std::to_string(layout.width) + "x" + std::to_string(layout.height) +
                     " is too large to decode"};
    cv::Mat image(static_cast<int>(layout.height), static_cast<int>(layout.width),
                  CV_MAKETYPE(layout.bitDepth == 16 ? CV_16U : CV_8U, layout.channels));
    std::vector<png_bytep> rows(layout.height);
    for (png_uint_32 y = 0; y < layout.height; ++y)
        rows[y] = image.ptr<png_byte>(static_cast<int>(y));
    if (!readPixels(s.png, rows.data()))
        return Error{std::string("not a valid PNG image: ") + io.message};
    return image;
}

Expected<cv::Mat> readPng(const std::string& path, PngPixels pixels) {
    auto bytes = base::readFile(path);
    if (!bytes)
        return bytes.error();
    auto image = decodePng(*bytes, pixels);
    if (!image)
        return Error{"cannot read " + path + ": " + image.error().message};
    return image;
}

Expected<std::vector<std::uint8_t>> encodePng(const cv::Mat& image, int compressionLevel) {
    const int type = image.type();
    if (image.empty() || (type != CV_8UC1 && type != CV_8UC3 && type != CV_8UC4 && type != CV_16UC1))
        return Error{"PNG encodes 8-bit gray, RGB, RGBA or 16-bit gray images, not this one"};
    std::vector<std::uint8_t> encoded;
    Io io;
    io.out = &encoded;
    WriteStructs s(io);
    if (!s.info)
        return Error{"cannot start the PNG encoder"};
    const Layout layout{static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
                        image.depth() == CV_16U ? 16 : 8, image.channels(), 0};
    std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
    for (int y = 0; y < image.rows; ++y)
        rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.ptr<png_byte>(y));
    if (!writeImage(s.png, s.info, layout, colorTypeOf(layout.channels), compressionLevel, rows.data()))
        return Error{std::string("cannot encode PNG: ") + io.message};
    return encoded;
}

Status writePng(const std::string& path, const cv::Mat& image, int compressionLevel) {
    auto encoded = encodePng(image, compressionLevel);
    if (!encoded)
        return Error{"cannot write " + path + ": " + encoded.error().message};
    return base::writeFileAtomically(path, *encoded);
}

} // namespace dc::frame
